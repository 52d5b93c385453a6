"""The main job's command line (scripts/damping_module.py, run by scripts/run): every option with
its unit and allowed values, parsed and checked before anything is filled or built.

parse(argv) returns (options, ModuleParams) or raises OptionError, whose text is the one line
the job prints before it exits with status 1:

    bad option --record-every: got nan; allowed [1e-06, 0.001] s (...)

run_settings(options) gives the run options as yadeflex.impact.run_impact takes them.
"""
import argparse
import dataclasses
import os

from . import checks as C
from .impact import ImpactTimes, RunSettings, EXIT
from .module import ModuleParams, FILLS, LIMITS, BOULDER_SHAPES, N_MODULES, SMALL

DEFAULT_RUN = ImpactTimes.MAX_AFTER_CONTACT  # [s] longest impact run without --duration (else until the rebound + a margin)
EXIT_CODES = ((EXIT["done"], "done"),
              (EXIT["failed"], "bad input (one line names the option and the values allowed) or another error"),
              (EXIT["unstable"], "a NaN, an unstable state or a collapsed time step (the message names the body)"),
              (EXIT["residual"], "the energy-balance residual exceeded --max-residual"),
              (EXIT["SIGINT"], "interrupted by SIGINT (Ctrl-C); summary.json: \"status\": \"interrupted\""),
              (EXIT["SIGTERM"], "interrupted by SIGTERM; summary.json: \"status\": \"interrupted\""))

# the job's own numeric options (the module's are ModuleParams' LIMITS)
RUN_LIMITS = dict(
    duration=C.Range(0.0, 2.0, "s", lo_open=True, note=f"simulated time after the first contact; default: until the rebound + {100 * ImpactTimes.REBOUND_MARGIN:g}%, "
                     f"at most {DEFAULT_RUN:g} s"),
    record_every=C.Range(1e-6, 1e-3, "s", note="time-series interval, at most duration/10: the impact force pulse lasts "
                         "10-50 ms and its peak needs ten records or more"),
    vtk_every=C.Range(1e-3, 2.0, "s", note=f"VTK frame interval, at most the run's length (--duration, else {DEFAULT_RUN:g} s): "
                      "a frame per millisecond at most"),
    min_dt_fraction=C.Range(0.0, 1.0, hi_open=True, note="stop if the stable time step falls below this fraction of its value at "
                            "impact; 0: never"),
    max_residual=C.Range(0.0, 1.0, lo_open=True, note="largest accepted energy-balance residual, fraction of the impact energy"),
)
DEFAULTS = {name: getattr(RunSettings, name) for name in RUN_LIMITS}
BOOLEAN_WORDS = "/".join(C.TRUE_WORDS[:2] + C.FALSE_WORDS[:2] + ("1", "0"))


class OptionError(Exception):
    """A refused command line: its text is one line naming the option and the values allowed."""


def _bad(option, value, allowed):
    return OptionError(f"bad option {option}: got {C.show(value)}; allowed {allowed}")


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        """argparse's own refusals (unknown option, missing value) as one OptionError line."""
        if message.startswith("unrecognized arguments: "):
            words = message.split(": ", 1)[1].split()
            raise OptionError(f"bad option {words[0]}: unknown option or stray value; allowed the options of --help")
        if message.startswith("argument "):
            option, what = message[len("argument "):].split(": ", 1)
            option = option.split("/")[0]
            action = next((a for a in self._actions if option in a.option_strings), None)
            allowed = None if action is None else "no value (a flag)" if action.nargs == 0 else action.help
            raise OptionError(f"bad option {option}: {what}" + (f"; allowed {allowed.replace('%%', '%')}" if allowed else ""))
        raise OptionError(message)


def _option(name):
    return "--" + name.replace("_", "-")


def _module_help(f):
    default = f.default
    small = f" (--small: {SMALL[f.name]:g})" if f.name in SMALL else ""
    if f.name in LIMITS:
        if default is None:
            default = {"impact_velocity": "from --drop-height", "grain_crushing_is50": "none (grains do not crush)"}.get(f.name, "the fill preset's")
        return f"{LIMITS[f.name].text()}; default {default}{small}"
    return {"lining": f"{BOOLEAN_WORDS}; default {default}", "rope": f"{BOOLEAN_WORDS}; default: with --n-modules above 1",
            "fill": f"one of {', '.join(sorted(FILLS))} (presets below); default {default}",
            "boulder_shape": f"one of {', '.join(BOULDER_SHAPES)}; default {default}",
            "n_modules": f"one of {', '.join(map(str, N_MODULES))} (in a row, hexagonal cluster); default {default}",
            "seed": f"a whole number in [0, {2 ** 31 - 1}]; default {default}",
            "impact_offset": "x y [m], two finite numbers within the module's radius; default 0 0"}[f.name]


def _epilog():
    fills = "\n".join(f"  {k}: grains {1e3 * v['grain_min']:g}-{1e3 * v['grain_max']:g} mm, density {v['density']:g} kg/m3, "
                      f"friction {v['friction_deg']:g} deg, modulus {v['young']:g} Pa, rolling friction {v['rolling_friction']:g}"
                      for k, v in sorted(FILLS.items()))
    codes = "\n".join(f"  {c}  {what}" for c, what in EXIT_CODES)
    return (f"fill presets (--fill; --grain-min, --grain-max, --fill-friction-deg, --fill-young, --rolling-friction override):\n{fills}\n"
            f"boulder shapes (--boulder-shape): cube (a rigid clump of 64 spheres with the cube's mass and inertia), sphere\n"
            f"scripts/run also takes --threads N: YADE's OpenMP threads, a whole number >= 1 (default 1)\n"
            f"exit status:\n{codes}\n"
            f"Every number must be finite; a scene over yadeflex.checks.MAX_BODIES = {C.MAX_BODIES} bodies is refused.")


def parser():
    ap = _Parser(prog="damping_module.py", description="Damping module hit by a boulder (yade-flex). Units are SI.",
                 epilog=_epilog(), formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)
    ap.add_argument("--out", default="results/module", help="results folder (created); default results/module")
    ap.add_argument("--cache-dir", default=None, help="folder of the cached filled modules (created); default ~/.cache/yadeflex/modules")
    ap.add_argument("--small", action="store_true", help="the reduced module for tests: 0.4 m x 0.3 m, 60-80 mm grains, 100 kg boulder dropped 1 m")
    ap.add_argument("--no-vtk", action="store_true", help="no VTK time series")
    ap.add_argument("--fill-only", action="store_true", help="fill the module into the cache (--cache-dir) and stop: no impact, "
                    "nothing written into --out (a study fills each module once this way before its runs)")
    for name, rng in RUN_LIMITS.items():
        ap.add_argument(_option(name), default=None, metavar="X", help=(rng.text() + ("" if DEFAULTS[name] is None else f"; default {DEFAULTS[name]}")).replace("%", "%%"))
    for f in dataclasses.fields(ModuleParams):
        ap.add_argument(_option(f.name), default=None, nargs=2 if f.name == "impact_offset" else None,
                        metavar=("X", "Y") if f.name == "impact_offset" else "V", help=_module_help(f).replace("%", "%%"))
    return ap


def _number(option, text, rng=C.Range()):
    try:
        x = float(text)
    except ValueError:
        raise _bad(option, text, "a number " + rng.text()) from None
    try:
        return C.number(option, x, rng)
    except C.BadValue as e:
        raise _bad(option, x, e.allowed) from None


def _folder(option, path):
    """A folder the job can create or write into, else OptionError."""
    if not path:
        raise _bad(option, path, "a folder path")
    p = os.path.abspath(path)
    while not os.path.exists(p):
        p = os.path.dirname(p)
    if not os.path.isdir(p) or not os.access(p, os.W_OK | os.X_OK):
        why = "not a folder" if not os.path.isdir(p) else "not writable"
        raise _bad(option, path, f"a folder that can be created or written into; {os.path.abspath(path)} cannot be written: {p} is {why}")
    return path


def parse(argv):
    """(options, ModuleParams) from the job's arguments, every value checked, or OptionError.
    --help prints the help and raises SystemExit(0)."""
    a = parser().parse_args(argv)
    _folder("--out", a.out)
    if a.cache_dir is not None:
        _folder("--cache-dir", a.cache_dir)
    for name, rng in RUN_LIMITS.items():
        v = getattr(a, name)
        setattr(a, name, DEFAULTS[name] if v is None else _number(_option(name), v, rng))
    run = a.duration if a.duration is not None else DEFAULT_RUN
    if a.record_every > run / 10:
        raise _bad("--record-every", a.record_every, f"at most duration/10 = {run / 10:g} s (ten records or more)")
    if a.vtk_every > run:
        raise _bad("--vtk-every", a.vtk_every, f"at most the run's length, {run:g} s")
    if a.drop_height is not None and a.impact_velocity is not None:  # (the speed would win without a word)
        raise OptionError(f"bad option --impact-velocity: got {C.show(a.impact_velocity)} with --drop-height {C.show(a.drop_height)}; "
                          "allowed one of the two (the drop height sets the speed, sqrt(2 g h))")
    p = ModuleParams.small() if a.small else ModuleParams()
    for f in dataclasses.fields(ModuleParams):
        v, opt = getattr(a, f.name), _option(f.name)
        if v is None:
            continue
        if f.name in ("lining", "rope"):
            v = _checked(opt, C.boolean, opt, v)
        elif f.name in ("seed", "n_modules"):
            try:
                v = int(v)
            except ValueError:
                raise _bad(opt, v, _module_help(f)) from None
        elif f.name == "impact_offset":
            try:
                v = C.vector(opt, [float(x) for x in v], 2)
            except (ValueError, C.BadValue):
                raise _bad(opt, tuple(v), _module_help(f)) from None
        elif f.name not in ("fill", "boulder_shape"):
            v = _number(opt, v, LIMITS[f.name])
        setattr(p, f.name, v)
    _checked(None, p.validate)
    return a, p


def _checked(option, check, *args):
    """check(*args), its BadValue as an OptionError naming `option` (None: the parameter it names)."""
    try:
        return check(*args)
    except C.BadValue as e:
        raise _bad(option or _option(e.name), e.value, e.allowed) from None


def run_settings(a):
    """The run options of parsed options `a` as yadeflex.impact.run_impact's keyword arguments
    (RunSettings' fields)."""
    return {f.name: getattr(a, f.name) for f in dataclasses.fields(RunSettings)}
