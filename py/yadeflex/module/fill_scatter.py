"""How much one run's answer depends on its fill: the fill-to-fill scatter measured on the default
and the reduced module, which a single run states beside its results (summary.json
`fill_scatter`, and its last line).

Each entry is a configuration run on several fills built alike (seeds 1-5) with the command it
names; its numbers are the coefficients of variation (standard deviation / mean) of the results
over those fills. A run of one of these configurations is told its own scatter; any other run the
default module's, as an order of magnitude, and how to measure its own (--seeds).
"""

# (the inputs that identify the configuration, the number of fills, the coefficients of variation, the command)
MEASURED = {
    "the default module": dict(
        match=dict(n_modules=1, diameter=1.0, height=0.6, fill="gravel", grain_min=0.032, grain_max=0.063, boulder_mass=800.0,
                   boulder_shape="cube", impact_velocity=6.264183905346329),
        n=5, cv=dict(peak_impact_force_filtered=0.0451, slab_force_max_filtered=0.0992, penetration_max=0.0558),
        command="scripts/run OUT --seeds 5"),
    "the reduced module": dict(
        match=dict(n_modules=1, diameter=0.4, height=0.3, fill="gravel", grain_min=0.06, grain_max=0.08, boulder_mass=100.0,
                   boulder_shape="cube", impact_velocity=4.4294469180700204),
        n=5, cv=dict(peak_impact_force_filtered=0.1017, slab_force_max_filtered=0.1729, penetration_max=0.0749),
        command="scripts/run OUT --small --seeds 5"),
}
WHAT = dict(peak_impact_force_filtered="peak force", slab_force_max_filtered="slab force", penetration_max="penetration")


def _matches(resolved, match):
    for k, v in match.items():
        got = resolved.get(k)
        if isinstance(v, float):
            if not isinstance(got, (int, float)) or abs(got - v) > 1e-9 * max(1.0, abs(v)):
                return False
        elif got != v:
            return False
    return True


def _cvs(entry):
    return ", ".join(f"{WHAT[k]} {100 * v:.0f}%" for k, v in entry["cv"].items() if v is not None)


def statement(resolved):
    """dict(text, measured_on, n, cv) for a run of the resolved parameters (ModuleParams.resolved())."""
    for name, e in MEASURED.items():
        if _matches(resolved, e["match"]):
            return dict(text=f"fills built alike scatter: on {name} (this configuration) one standard deviation is {_cvs(e)} of the mean "
                             f"over {e['n']} fills ({e['command']}); a design value needs several fills (--seeds 5)",
                        measured_on=name, n=e["n"], cv=dict(e["cv"]))
    e = MEASURED["the default module"]
    return dict(text=f"fills built alike scatter: on the default module one standard deviation is {_cvs(e)} of the mean over "
                     f"{e['n']} fills; this configuration's own scatter is not measured: run it with --seeds 5",
                measured_on=None, n=None, cv=None)
