"""The main job's command line (scripts/damping_module.py, run by scripts/run): every option with
its unit and allowed values, parsed and checked before anything is filled or built.

parse(argv) returns (options, ModuleParams) or raises OptionError, whose text is the one line
the job prints before it exits with status 1:

    bad option --record-every: got nan; allowed [1e-06, 0.001] s (...)

run_settings(options) gives the run options as yadeflex.module.impact.run_impact takes them.
"""
import argparse
import dataclasses
import os

from .. import checks as C
from ..runner import ImpactTimes, RunSettings, EXIT
from .. import params as P
from ..module import ModuleParams, FILLS, PARAMS

DEFAULT_RUN = ImpactTimes.MAX_AFTER_CONTACT  # [s] longest impact run without --duration (else until the rebound + a margin)
EXIT_CODES = ((EXIT["done"], "done"),
              (EXIT["failed"], "bad input (one line names the option and the values allowed) or another error"),
              (EXIT["unstable"], "a NaN, an unstable state or a collapsed time step (the message names the body)"),
              (EXIT["residual"], "the energy-balance residual exceeded --max-residual"),
              (EXIT["SIGINT"], "interrupted by SIGINT (Ctrl-C); summary.json: \"status\": \"interrupted\""),
              (EXIT["SIGTERM"], "interrupted by SIGTERM; summary.json: \"status\": \"interrupted\""))

RUN_PARAMS = {k: fp for k, fp in P.declared(RunSettings).items() if fp[1].kind != "flag"}  # the job's own options with a value
RUN_LIMITS = {k: p.allowed for k, (_, p) in RUN_PARAMS.items()}
DEFAULTS = {name: f.default for name, (f, _) in RUN_PARAMS.items()}


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


_option = P.option


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


MAX_SEEDS = 1000  # runs of one configuration (each a fill of its own)
MAX_SEED = 2 ** 31 - 1  # the largest --seed


def parser():
    ap = _Parser(prog="damping_module.py", description="Damping module hit by a boulder (yade-flex). Units are SI.",
                 epilog=_epilog(), formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)
    ap.add_argument("--out", default="results/module", help="results folder (created); default results/module")
    ap.add_argument("--cache-dir", default=None, help="folder of the cached filled modules (created); default ~/.cache/yadeflex/modules")
    ap.add_argument("--small", action="store_true", help="the reduced module for tests: 0.4 m x 0.3 m, 60-80 mm grains, 100 kg boulder dropped 1 m")
    ap.add_argument("--no-vtk", action="store_true", help="no VTK time series")
    ap.add_argument("--fill-only", action="store_true", help="fill the module into the cache (--cache-dir) and stop: no impact, "
                    "nothing written into --out (a study fills each module once this way before its runs)")
    ap.add_argument("--seeds", default=None, metavar="N", help="runs on N fills built alike (seeds --seed, --seed+1, ...; N whole, "
                    f"1-{MAX_SEEDS}), each into OUT/seedS/, and the scatter of their results: OUT/configurations.csv, OUT/summary.json, "
                    "OUT/scatter.png (default 1: one run into OUT)")
    for name, (f, p) in RUN_PARAMS.items():
        ap.add_argument(_option(name), default=None, metavar="X", help=P.help_text(f, p).replace("%", "%%"))
    for name, (f, p) in PARAMS.items():
        ap.add_argument(_option(name), default=None, nargs=2 if p.kind == "pair" else None,
                        metavar=("X", "Y") if p.kind == "pair" else "V", help=P.help_text(f, p).replace("%", "%%"))
    return ap


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
    given = a.seeds
    try:
        a.seeds = 1 if given is None else int(given)
        if not 1 <= a.seeds <= MAX_SEEDS:
            raise ValueError
    except ValueError:
        raise _bad("--seeds", given, f"a whole number in [1, {MAX_SEEDS}] (a fill each)") from None
    for name, (f, p) in RUN_PARAMS.items():
        v = getattr(a, name)
        setattr(a, name, f.default if v is None else _checked(_option(name), p.parse, name, v))
    run = a.duration if a.duration is not None else DEFAULT_RUN
    if a.record_every > run / 10:
        raise _bad("--record-every", a.record_every, f"at most duration/10 = {run / 10:g} s (ten records or more)")
    if a.vtk_every > run:
        raise _bad("--vtk-every", a.vtk_every, f"at most the run's length, {run:g} s")
    if a.drop_height is not None and a.impact_velocity is not None:  # (the speed would win without a word)
        raise OptionError(f"bad option --impact-velocity: got {C.show(a.impact_velocity)} with --drop-height {C.show(a.drop_height)}; "
                          "allowed one of the two (the drop height sets the speed, sqrt(2 g h))")
    p = ModuleParams.small() if a.small else ModuleParams()
    for name, (f, prm) in PARAMS.items():
        v = getattr(a, name)
        if v is not None:
            setattr(p, name, _checked(_option(name), prm.parse, name, v))
    _checked(None, p.validate)
    if p.seed + a.seeds - 1 > MAX_SEED:
        raise _bad("--seeds", given, f"at most {MAX_SEED - p.seed + 1} from --seed {p.seed} (seeds up to {MAX_SEED})")
    return a, p


def _checked(option, check, *args):
    """check(*args), its BadValue as an OptionError naming `option` (None: the parameter it names)."""
    try:
        return check(*args)
    except C.BadValue as e:
        raise _bad(option or _option(e.name), e.value, e.allowed) from None


def run_settings(a):
    """The run options of parsed options `a` as yadeflex.module.impact.run_impact's keyword arguments
    (RunSettings' fields)."""
    return {f.name: getattr(a, f.name) for f in dataclasses.fields(RunSettings)}


README_TABLE = ("<!-- options: written by scripts/options_table.py from the declarations -->", "<!-- end of options -->")


def readme_table():
    """The README's option table (markdown lines, between the README_TABLE markers), read from
    the declarations of ModuleParams' and RunSettings' fields."""
    return [README_TABLE[0]] + P.table(ModuleParams, RunSettings) + [README_TABLE[1]]


def readme_with_table(text):
    """README text with the option table between its markers replaced by readme_table()."""
    lines = text.split("\n")
    try:
        a, b = lines.index(README_TABLE[0]), lines.index(README_TABLE[1])
    except ValueError:
        raise ValueError(f"the README has no option table between {README_TABLE[0]} and {README_TABLE[1]}") from None
    return "\n".join(lines[:a] + readme_table() + lines[b + 1:])
