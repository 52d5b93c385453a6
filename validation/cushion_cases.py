"""The module's peak impact force against the empirical cushion formulas (yadeflex.module.cushion:
Labiouse 1996, JRA 2000, ASTRA 2008) over drop height and boulder mass, on the reduced module
(yadeflex.module.ModuleParams.small, run by yadeflex.module.impact.run_impact as the main job runs)."""
import math
import os

from yadeflex.module import cushion
from yadeflex.module.impact import run_impact
from yadeflex.module import ModuleParams, FILLS
from yadeflex.harness.verdict import Case, grade

GROUP = "Damping module against the cushion formulas (reduced module: 0.4 x 0.3 m, grains of 60-80 mm)"
PLOTS = [("plots/cushion.png", "peak force against drop height and mass")]  # (path under OUT, title), shown under the group's table
# the values used before the fill was measured, kept for comparison in each case's details
ASSUMED = dict(M_E=5000e3, lame=1000e3)  # [Pa] an assumed loose-gravel plate-load modulus; JRA 2000's design value for a sand cushion


EXPONENT_TOL = 0.1
EXPONENT_WHY = ("all three formulas have the height exponent 3/5 of Hertz's elastic impact; their mass exponents at a constant block "
                "size are 0.6 (Labiouse, ASTRA) and 2/3 (JRA). 0.1 is a judgement fixed here, wider than the formulas' spread (0.067); "
                "the papers' own scatter is not in the repository")


def _impact(p, out, cache_dir, key):
    s = run_impact(p, os.path.join(out, "runs", key), cache_dir=cache_dir, progress=False, no_vtk=True)
    ok = s.get("status") == "done"
    return dict(peak=s.get("peak_impact_force") if ok else math.nan, penetration=s.get("penetration_max") if ok else math.nan,
                status=s.get("status"), residual=s.get("energy_residual_max_fraction"))


def _formulas(p, height, props=None):
    f = props or cushion.fill_properties(p.fill)
    return cushion.formulas(p.boulder_mass, height, cushion.equivalent_radius(p.boulder_mass, p.boulder_density), f["M_E"], f["lame"], p.height, f["friction_deg"])


def run(full, out, cache_dir=None):
    heights = (0.25, 0.5, 1.0, 2.0, 4.0) if full else (0.5, 1.0, 2.0)
    masses = (25.0, 50.0, 100.0, 200.0, 400.0) if full else (50.0, 100.0, 200.0)
    base = ModuleParams.small()
    size = base.boulder_size()
    runs = {}
    for h in heights:
        p = ModuleParams.small(drop_height=h)
        runs[("H", h)] = dict(_impact(p, out, cache_dir, f"H{h:g}"), params=p, height=h, mass=p.boulder_mass)
    for m in masses:
        if m == base.boulder_mass and ("H", base.drop_height) in runs:
            runs[("m", m)] = runs[("H", base.drop_height)]
            continue
        p = ModuleParams.small(boulder_mass=m, boulder_density=m / size ** 3)  # the same cube, another density
        runs[("m", m)] = dict(_impact(p, out, cache_dir, f"m{m:g}"), params=p, height=base.drop_height, mass=m)
    res = []
    props = cushion.fill_properties(base.fill)

    def fit(key, xs):
        pts = [(x, runs[(key, x)]["peak"]) for x in xs if math.isfinite(runs[(key, x)]["peak"])]
        return cushion.power_fit([a for a, _ in pts], [b for _, b in pts])[1] if len(pts) >= 2 else math.nan

    c = Case(name="cushion_height_exponent", group=GROUP, quantity=f"exponent b of peak force ~ H^b, {base.boulder_mass:g} kg cube, H = {', '.join(f'{h:g}' for h in heights)} m",
             reference=0.6, source="Labiouse 1996, JRA 2000, ASTRA 2008: F ~ H^0.6", tolerance=EXPONENT_TOL, kind="absolute",
             justification=EXPONENT_WHY)
    pen = [(h, runs[("H", h)]["penetration"]) for h in heights if runs[("H", h)]["penetration"] > 0]
    res.append(grade(c, fit("H", heights), penetration_exponent=cushion.power_fit(*zip(*pen))[1] if len(pen) >= 2 else None,
                     penetration_exponent_hertz=0.4))
    c = Case(name="cushion_mass_exponent", group=GROUP, quantity=f"exponent b of peak force ~ m^b at a constant cube size {size:.3f} m, H = {base.drop_height:g} m, m = {', '.join(f'{m:g}' for m in masses)} kg",
             reference=0.6, source="Labiouse 1996, ASTRA 2008: F ~ m^0.6 at constant R; JRA 2000: m^(2/3)", tolerance=EXPONENT_TOL, kind="absolute",
             justification=EXPONENT_WHY)
    c.open = ("issue 36, section 2: on the full-size module the peak is the larger of an early, inertial peak (little dependent on the mass) "
              "and a late one at the deepest point, where the fill locks up; the lock-up is driven by the confinement of the fill between "
              "the boulder and the mesh (a wider module hardly locks up) and by the grains' stiffness, not by rolling resistance "
              "(validation/studies/fill_factors); a looser fill lowers the early peak but locks up deeper and steepens the exponent "
              "(validation/studies/fill_density: 0.75-0.77 against 0.58); grains of moderately strong rock (point-load index 1.5 MPa) would "
              "break by the hundreds under the 1600 kg boulder, most of them in the lock-up, but with contacts that yield at that load the "
              "mass exponent stays (0.63-0.66 against 0.57-0.64 from 400 to 1600 kg) while the height exponent falls to 0.65-0.67 "
              "(validation/studies/grain_crushing); grain shape is not modelled beyond rolling resistance. On the reduced "
              "module a single run's peak moves by up to 10% with a 10-30% change of the time step (with the lining scaled or at its own "
              "mass), so an exponent from three single runs over a 4x mass range is known to about 0.1, the tolerance")
    res.append(grade(c, fit("m", masses)))
    for key, r in sorted(runs.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        if key[0] == "m" and r is runs.get(("H", base.drop_height)):
            continue
        f = _formulas(r["params"], r["height"])
        band = (min(f.values()) / 1e3, max(f.values()) / 1e3)
        fa = _formulas(r["params"], r["height"], dict(ASSUMED, friction_deg=FILLS[r["params"].fill]["friction_deg"]))
        c = Case(name=f"cushion_peak_{key[0]}{key[1]:g}", group=GROUP,
                 quantity=f"peak force [kN], {r['mass']:g} kg from {r['height']:g} m", reference=band,
                 source=f"the band of the three formulas at the model fill's own M_E = {props['M_E'] / 1e3:.0f} kN/m2 (plate-load test, {cushion.PLATE_RANGE}), "
                        f"lambda = {props['lame'] / 1e3:.0f} kN/m2 (oedometer, {cushion.LAME_RANGE}) and phi = {props['friction_deg']:.1f} deg "
                        "(angle of repose), measured by validation/fill_calibration.py; e = module height",
                 tolerance=0.0, kind="band", justification="the formulas' own disagreement at these parameters is the band")
        res.append(grade(c, r["peak"] / 1e3, penetration_m=r["penetration"], status=r["status"], energy_residual=r["residual"],
                         formulas_kN={k: v / 1e3 for k, v in f.items()}, height=r["height"], mass=r["mass"],
                         band_at_assumed_moduli_kN=[min(fa.values()) / 1e3, max(fa.values()) / 1e3]))
        if res[-1].verdict != "PASS" and r["peak"] / 1e3 > band[1]:
            res[-1].open = ("issue 36, section 2: above the band: past a quarter of the module's height the fill locks up between the boulder and "
                            "the mesh (cushion_mass_exponent), which the formulas' cushion layers do not")
        elif res[-1].verdict != "PASS":
            res[-1].open = ("issue 36, section 2: below the band at the fill's measured moduli; the plate-load modulus scatters widely from "
                            "fill to fill (validation/calibration), and the band moves as M_E^0.4")
    _plot(os.path.join(out, "cushion.png"), runs, heights, masses)
    return res


def _plot(path, runs, heights, masses):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key, xs, xl in ((axs[0], "H", heights, "drop height H [m]"), (axs[1], "m", masses, "boulder mass m [kg] (same cube size)")):
        pts = [(x, runs[(key, x)]["peak"] / 1e3) for x in xs if math.isfinite(runs[(key, x)]["peak"])]
        ax.loglog([a for a, _ in pts], [b for _, b in pts], "ko-", label="yade-flex (small module)")
        for name in ("Labiouse 1996", "JRA 2000", "ASTRA 2008"):
            ax.loglog(xs, [_formulas(runs[(key, x)]["params"], runs[(key, x)]["height"])[name] / 1e3 for x in xs], "--", label=name)
        ax.set_xlabel(xl)
        ax.set_ylabel("peak force [kN]")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
