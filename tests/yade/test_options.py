"""The main job's options (scripts/damping_module.py, scripts/run): every option is checked
before anything is filled or built; a bad value ends the job with status 1 and one line on
stderr that names the option and the values allowed; --help gives every option's unit and
values, the presets, the exit codes and scripts/run's --threads."""
import os
import subprocess

import pytest

from conftest import REPO
from yadeflex.module import cli as cli
from yadeflex.module import FILLS, ModuleParams

SCRIPT = os.path.join(REPO, "scripts", "damping_module.py")
YADE_BANNER = ("Welcome to Yade", "Using python", "TCP python prompt", "XMLRPC info provider", "Running script")  # yade-double's own lines

# (arguments, the option the message must name): at least one bad value for every option
BAD = [
    (["--out", ""], "--out"), (["--out", "/etc/hostname/x"], "--out"), (["--cache-dir", "/etc/hostname"], "--cache-dir"),
    (["--cache-dir"], "--cache-dir"),
    (["--small=yes"], "--small"), (["--no-vtk=1"], "--no-vtk"), (["--fill-only=1"], "--fill-only"),
    (["--duration", "-1"], "--duration"), (["--duration", "nan"], "--duration"), (["--duration", "0"], "--duration"),
    (["--duration", "1e9"], "--duration"), (["--duration", "soon"], "--duration"), (["--duration"], "--duration"),
    (["--record-every", "nan"], "--record-every"), (["--record-every", "0"], "--record-every"), (["--record-every", "-1e-4"], "--record-every"),
    (["--record-every", "0.1"], "--record-every"), (["--duration", "0.005", "--record-every", "0.001"], "--record-every"),
    (["--vtk-every", "0"], "--vtk-every"), (["--vtk-every", "1e-6"], "--vtk-every"), (["--vtk-every", "inf"], "--vtk-every"),
    (["--duration", "0.01", "--vtk-every", "0.05"], "--vtk-every"),
    (["--min-dt-fraction", "1"], "--min-dt-fraction"), (["--min-dt-fraction", "nan"], "--min-dt-fraction"),
    (["--min-dt-fraction", "-0.1"], "--min-dt-fraction"),
    (["--max-residual", "0"], "--max-residual"), (["--max-residual", "nan"], "--max-residual"), (["--max-residual", "2"], "--max-residual"),
    (["--diameter", "-1"], "--diameter"), (["--diameter", "1e300"], "--diameter"), (["--diameter", "nan"], "--diameter"),
    (["--diameter", "0.01"], "--diameter"), (["--diameter", "20"], "--diameter"),
    (["--height", "0"], "--height"), (["--height", "inf"], "--height"), (["--height", "1e4"], "--height"),
    (["--ring-bar-diameter", "0"], "--ring-bar-diameter"), (["--ring-bar-diameter", "1"], "--ring-bar-diameter"),
    (["--lining", "maybe"], "--lining"), (["--lining", "2"], "--lining"), (["--lining", ""], "--lining"),
    (["--lining-thickness", "-0.002"], "--lining-thickness"), (["--lining-thickness", "0.5"], "--lining-thickness"),
    (["--lining-gap", "-0.01"], "--lining-gap"), (["--lining-gap", "0.3"], "--lining-gap"), (["--lining-gap", "nan"], "--lining-gap"),
    (["--fill", "marbles"], "--fill"), (["--fill", "GRAVEL"], "--fill"), (["--fill", "cellular_glass"], "--fill"),
    (["--grain-min", "0"], "--grain-min"), (["--grain-min", "0.05", "--grain-max", "0.01"], "--grain-min"),
    (["--grain-min", "1e-6"], "--grain-min"),
    (["--grain-max", "nan"], "--grain-max"), (["--grain-max", "0.5"], "--grain-max"),
    (["--grain-max", "0.002", "--grain-min", "0.002"], "--grain-max"),
    (["--fill-friction-deg", "90"], "--fill-friction-deg"), (["--fill-friction-deg", "-5"], "--fill-friction-deg"),
    (["--rolling-friction", "-0.1"], "--rolling-friction"), (["--rolling-friction", "inf"], "--rolling-friction"),
    (["--fill-young", "0"], "--fill-young"), (["--fill-young", "1e300"], "--fill-young"),
    (["--grain-crushing-is50", "-1e6"], "--grain-crushing-is50"), (["--grain-crushing-is50", "nan"], "--grain-crushing-is50"),
    (["--fill-deposition-friction-deg", "-1"], "--fill-deposition-friction-deg"),
    (["--fill-deposition-friction-deg", "nan"], "--fill-deposition-friction-deg"),
    (["--fill-deposition-friction-deg", "39"], "--fill-deposition-friction-deg"),  # above gravel's 38
    (["--fill-deposition-friction-deg", "30", "--fill-friction-deg", "25"], "--fill-deposition-friction-deg"),
    (["--boulder-mass", "0"], "--boulder-mass"), (["--boulder-mass", "1e300"], "--boulder-mass"), (["--boulder-mass", "1e-300"], "--boulder-mass"),
    (["--boulder-shape", "pyramid"], "--boulder-shape"),
    (["--boulder-density", "0"], "--boulder-density"), (["--boulder-density", "1e9"], "--boulder-density"),
    (["--drop-height", "0"], "--drop-height"), (["--drop-height", "1e300"], "--drop-height"), (["--drop-height", "nan"], "--drop-height"),
    (["--impact-velocity", "-3"], "--impact-velocity"), (["--impact-velocity", "1e9"], "--impact-velocity"),
    (["--drop-height", "1", "--impact-velocity", "3"], "--impact-velocity"),  # two speeds: the velocity won without a word
    (["--impact-offset", "nan", "0"], "--impact-offset"), (["--impact-offset", "3", "0"], "--impact-offset"),
    (["--impact-offset", "0"], "--impact-offset"),
    (["--damping", "1"], "--damping"), (["--damping", "-0.1"], "--damping"),
    (["--settle-damping", "0"], "--settle-damping"), (["--settle-damping", "1"], "--settle-damping"),
    (["--timestep-safety", "0"], "--timestep-safety"), (["--timestep-safety", "1e-300"], "--timestep-safety"),
    (["--timestep-safety", "2"], "--timestep-safety"),
    (["--steel-contact-young", "-1"], "--steel-contact-young"), (["--steel-contact-young", "1e20"], "--steel-contact-young"),
    (["--lining-node-mass", "-0.01"], "--lining-node-mass"), (["--lining-node-mass", "nan"], "--lining-node-mass"),
    (["--lining-node-mass", "5"], "--lining-node-mass"),
    (["--seed", "1.5"], "--seed"), (["--seed", "-1"], "--seed"), (["--seed", "1e40"], "--seed"),
    (["--seeds", "0"], "--seeds"), (["--seeds", "1.5"], "--seeds"), (["--seeds", "1001"], "--seeds"),
    (["--seed", "2147483647", "--seeds", "2"], "--seeds"),
    (["--n-modules", "2"], "--n-modules"), (["--n-modules", "three"], "--n-modules"),
    (["--module-gap", "-0.02"], "--module-gap"), (["--module-gap", "5"], "--module-gap"),
    (["--rope", "perhaps"], "--rope"),
    (["--no-such-option", "1"], "--no-such-option"), (["--diam", "1"], "--diam"),
]


def _options():
    return {s for a in cli.parser()._actions for s in a.option_strings if s not in ("-h", "--help")}


def test_every_option_has_a_bad_case():
    """The table covers every option the job takes (a new option needs its bad values here)."""
    assert _options() <= {args[0].split("=")[0] for args, _ in BAD}


@pytest.mark.parametrize("args, option", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_option_is_one_line_naming_it(args, option):
    with pytest.raises(cli.OptionError) as err:
        cli.parse(["--small", *args] if args[0] != "--small=yes" else args)
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(f"bad option {option}:"), msg
    assert "allowed" in msg, msg


def test_a_withdrawn_fill_preset_is_refused_with_its_reason():
    """cellular_glass is not offered (its grains would need to crush): refused by the job and by
    ModuleParams, naming the reason and the presets there are; not listed in --help."""
    with pytest.raises(cli.OptionError) as err:
        cli.parse(["--small", "--fill", "cellular_glass"])
    assert str(err.value).startswith("bad option --fill: got 'cellular_glass'; allowed one of 'gravel', 'sand' (cellular_glass is withdrawn: "), err.value
    assert "crush" in str(err.value)
    with pytest.raises(ValueError, match="cellular_glass is withdrawn: .*do not crush"):
        ModuleParams(fill="cellular_glass").validate()
    assert "cellular_glass" not in FILLS and "cellular_glass:" not in cli.parser().format_help()


@pytest.mark.parametrize("word, value", [("true", True), ("YES", True), ("1", True), ("False", False), ("no", False), ("0", False)])
def test_booleans_take_only_true_false_yes_no_1_0(word, value):
    _, p = cli.parse(["--small", "--lining", word, "--rope", word])
    assert p.lining is value and p.rope is value


def test_good_options_give_the_values_asked():
    a, p = cli.parse(["--small", "--duration", "0.05", "--record-every", "1e-4", "--vtk-every", "0.01", "--fill", "sand",
                      "--impact-offset", "0.05", "-0.02", "--seed", "7", "--n-modules", "3"])
    assert (a.duration, a.record_every, a.vtk_every) == (0.05, 1e-4, 0.01)
    assert (p.fill, p.impact_offset, p.seed, p.n_modules, p.diameter) == ("sand", (0.05, -0.02), 7, 3, 0.4)


def test_help_gives_units_values_presets_exit_codes_and_threads():
    h = cli.parser().format_help()
    for opt in _options():
        assert opt in h, opt
    for words in ("--threads", "exit status", "0  done", "1  bad input", "2  a NaN", "3  the energy-balance residual",
                  "cube", "sphere", "[1e-06, 0.001] s", ">= 0.2 m", "true/yes/false/no/1/0", *FILLS):
        assert words in h, words
    for k, v in FILLS.items():
        assert f"{k}: grains {1e3 * v['grain_min']:g}-{1e3 * v['grain_max']:g} mm" in h


def _job(tmp_path, *args):
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.join(REPO, "py"))
    return subprocess.run(["yade-double", "-n", "-j1", "-x", SCRIPT, "--out", str(tmp_path / "out"), "--cache-dir", str(tmp_path / "cache"),
                           *args], capture_output=True, text=True, timeout=120, env=env, cwd=REPO)


@pytest.mark.parametrize("args, option", [
    (["--record-every", "nan"], "--record-every"), (["--duration", "-1"], "--duration"),
    (["--impact-offset", "nan", "0"], "--impact-offset"), (["--lining", "maybe"], "--lining"),
    (["--diameter", "1e300"], "--diameter"), (["--vtk-every", "0"], "--vtk-every"),
    (["--min-dt-fraction", "1"], "--min-dt-fraction"), (["--bogus"], "--bogus"),
])
def test_the_job_exits_1_with_one_line_before_filling(tmp_path, args, option):
    """Through yade-double: status 1, stderr one line naming the option (no traceback), and
    nothing filled, cached or written."""
    r = _job(tmp_path, "--small", *args)
    assert r.returncode == 1, (r.returncode, r.stderr[-2000:])
    lines = [ln for ln in r.stderr.strip().splitlines() if not ln.startswith(YADE_BANNER)]
    assert len(lines) == 1 and lines[0].startswith(f"damping_module: bad option {option}:"), r.stderr
    assert "Traceback" not in r.stdout + r.stderr and "filled module" not in r.stdout
    assert not (tmp_path / "cache").exists() and not (tmp_path / "out").exists()


def test_help_exits_0(tmp_path):
    r = _job(tmp_path, "--help")
    assert r.returncode == 0 and "--threads" in r.stdout and "exit status" in r.stdout


def test_resolved_values_are_the_presets_with_the_overrides():
    from yadeflex.module import ModuleParams
    r = ModuleParams(fill="sand", fill_young=5e7, impact_velocity=6.0).resolved()
    sand = FILLS["sand"]
    assert (r["grain_min"], r["grain_max"], r["fill_density"], r["fill_friction_deg"], r["rolling_friction"]) == (
        sand["grain_min"], sand["grain_max"], sand["density"], sand["friction_deg"], sand["rolling_friction"])
    assert r["fill_young"] == 5e7 and r["impact_velocity"] == 6.0 and r["rope"] is False


def test_more_threads_than_cpus_are_refused(tmp_path):
    """YADE's ForceResetter crashed with --threads 100000 (exit 139, summary left "running"): both
    the main job (yade-double -j) and scripts/run refuse more threads than the CPUs available,
    status 1 and one line, nothing filled or written."""
    cpus = len(os.sched_getaffinity(0))
    env = dict(os.environ, PYTHONPATH=os.path.join(REPO, "py"))
    r = subprocess.run(["yade-double", "-n", "-j", str(cpus + 1), "-x", SCRIPT, "--out", str(tmp_path / "out"), "--cache-dir", str(tmp_path / "cache"),
                        "--small"], capture_output=True, text=True, timeout=300, env=env, cwd=str(tmp_path))
    lines = [ln for ln in r.stderr.strip().splitlines() if not ln.startswith(YADE_BANNER)]
    assert r.returncode == 1 and len(lines) == 1 and f"but {cpus} CPUs are available" in lines[0], r.stderr
    r = subprocess.run([os.path.join(REPO, "scripts", "run"), str(tmp_path / "out2"), "--threads", "100000", "--small"], capture_output=True, text=True,
                       timeout=300, cwd=str(tmp_path))
    assert r.returncode == 1 and f"more than the {cpus} CPUs available" in r.stderr, r.stderr
    assert not (tmp_path / "cache").exists() and not (tmp_path / "out").exists() and not (tmp_path / "out2").exists()


def test_the_readme_option_table_is_the_one_the_declarations_give():
    # one home per option: the README's table is written from ModuleParams' and RunSettings'
    # declarations (scripts/options_table.py --write), every option of --help in it once
    with open(os.path.join(REPO, "README.md")) as f:
        text = f.read()
    assert cli.readme_with_table(text) == text, "README's option table is stale: run yade-double -n -x scripts/options_table.py --write"
    table = "\n".join(cli.readme_table())
    for name in list(cli.PARAMS) + list(cli.P.declared(cli.RunSettings)):
        assert table.count(f"`{cli.P.option(name)}`") == 1, name


def test_the_fill_cache_key_holds_the_fill_stage_only():
    # the filled module depends on the fields declared for the fill stage: an impact field
    # changes no key, every fill field does
    base = ModuleParams()
    for name, (f, p) in cli.PARAMS.items():
        other = {"number": lambda v: (v or 0.5) * 0.99 if name != "fill_deposition_friction_deg" else 10.0, "integer": lambda v: v + 1,
                 "boolean": lambda v: not v, "choice": lambda v: next(o for o in p.allowed if o != v and o is not None),
                 "pair": lambda v: (0.1, 0.0)}[p.kind](f.default)
        unset = dict(grain_min=0.035, grain_max=0.06, fill_friction_deg=30.0, rolling_friction=0.2, fill_young=2e8, grain_crushing_is50=5e6,
                     impact_velocity=5.0, rope=True, lining_gap=0.03)  # (values for the unset ones; a gap that moves the lining)
        other = unset.get(name, other)
        changed = ModuleParams(**{name: other})
        changed.validate()
        assert (changed.fill_key() != base.fill_key()) == (p.stage == "fill"), (name, p.stage, other)
