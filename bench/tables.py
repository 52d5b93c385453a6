# Regenerates the tables of bench/README.md that are copies of CSV files in bench/results: each sits
# between the markers <!-- table:NAME --> and <!-- /table:NAME -->, and TABLES below says which CSV,
# which rows and columns, and how each is formatted. Plain Python (no YADE).
#
#     python3 bench/tables.py            # rewrite the marked blocks in place
#     python3 bench/tables.py --check    # exit 1 (and name them) if a block differs from its CSV
import argparse
import csv
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

SCENES = {"helix": "helix, 200 segments", "net": "net 20×20 + sphere at 5 m/s", "sheet": "sheet under a 5 kg sphere",
          "bumpy": "sphere rolling over a fixed bumpy surface"}


def fixed(digits):
    return lambda v: f"{float(v):.{digits}f}"


def times(digits):
    return lambda v: f"{float(v):.{digits}f}x"


def text(v):
    return v


def scene(v):
    return SCENES.get(v, v)


def _cantilever(rows):
    """One row per (load, segments), the built-in and ours side by side."""
    by = {}
    for r in rows:
        by.setdefault((r["load"], int(r["segments"])), {})[r["impl"]] = r
    order = sorted(by, key=lambda k: (k[0] != "tip", k[1]))
    return [dict(load=k[0], segments=str(k[1]), builtin=by[k]["builtin"]["ratio"], flex=by[k]["flex"]["ratio"]) for k in order]


def _time_to_result(rows):
    return [dict(r, speedup=float(r["before_s"]) / float(r["after_s"])) for r in rows]


def _lammps(rows):
    return [dict(r, ratio_text=f"{float(r['ratio']):.2f}x ({r['ratio_range']})", over_plain=1 / float(r["yadeflex_over_plain"])) for r in rows]


def _lammps_sections(rows):
    """One row per case: each part's time, ours and LAMMPS's side by side."""
    by = {}
    for r in rows:
        c = by.setdefault(r["case"], dict(case=r["case"]))
        c[r["part"] + "|y"] = r["yadeflex_us_per_particle_step"]
        c[r["part"] + "|l"] = r["lammps_us_per_particle_step"]
    return list(by.values())


def _grain_kernel(rows):
    return [dict(r, kernel_text=f"{float(r['kernel_us']):.3f} ({r['kernel_range']})", plugin_text=f"{float(r['plugin_us']):.3f} ({r['plugin_range']})",
                 lammps_text=f"{float(r['lammps_us']):.3f} ({r['lammps_range']})", engine_text=f"{float(r['engine_us']):.3f} ({r['engine_range']})") for r in rows]


def _impact_budget(rows):
    """One row per part: one thread and two side by side, with the speed-up of two."""
    by = {}
    for r in rows:
        c = by.setdefault(r["part"], dict(part=r["part"], s1="", us1="", share1="", s2="", us2="", speedup=""))
        if r["threads"] in ("1", "2"):
            t = r["threads"]
            c["s" + t], c["us" + t] = r["seconds"], r["us_per_step"]
            if t == "1":
                c["share1"] = f"{100 * float(r['share']):.0f}%"
    for c in by.values():
        if c["s1"] and c["s2"] and float(c["s2"]) > 0:
            c["speedup"] = f"{float(c['s1']) / float(c['s2']):.2f}x"
    return list(by.values())


# name: csv (in results/), optional rows (a function of the CSV's rows), columns (header, key, format)
TABLES = {
    "grain_kernel": dict(csv="grain_kernel.csv", rows=_grain_kernel, columns=[
        ("case (one thread)", "case", text), ("kernel µs/particle-step", "kernel_text", text), ("plugin, grain contacts in the loop", "plugin_text", text),
        ("plugin with FlexGrainEngine", "engine_text", text), ("LAMMPS", "lammps_text", text), ("LAMMPS law", "lammps_law", text),
        ("kernel / LAMMPS", "kernel_over_lammps", times(2)), ("plugin / LAMMPS", "plugin_over_lammps", times(2)),
        ("with FlexGrainEngine / LAMMPS", "engine_over_lammps", times(2)), ("plugin / kernel", "plugin_over_kernel", times(2)),
        ("kernel's speed-up on two threads", "kernel_two_threads_speedup", lambda v: f"{float(v):.2f}x" if v else "")]),
    "lammps_grains": dict(csv="lammps_grains.csv", rows=_lammps, columns=[
        ("case (one thread)", "case", text), ("yade-flex µs/particle-step", "yadeflex_us_per_particle_step", fixed(3)),
        ("LAMMPS", "lammps_us_per_particle_step", fixed(3)), ("ratio (range)", "ratio_text", text), ("LAMMPS law", "lammps_law", text),
        ("plain YADE", "plain_yade_us", fixed(3)), ("yade-flex faster than plain YADE", "over_plain", times(1))]),
    "lammps_grains_sections": dict(csv="lammps_grains_sections.csv", rows=_lammps_sections, columns=[
        ("case (one thread), µs/particle-step", "case", text), ("grain-grain: yade-flex's grain engine", "grain-grain contacts|y", fixed(3)),
        ("LAMMPS Pair", "grain-grain contacts|l", fixed(3)), ("walls and facets: YADE's loop", "walls and facets|y", fixed(3)),
        ("integration: ours", "integration|y", fixed(3)), ("LAMMPS Modify (integration, walls)", "LAMMPS fixes: integration, walls|l", fixed(3)),
        ("YADE's collider", "neighbour lists|y", fixed(3)), ("LAMMPS Neigh", "neighbour lists|l", fixed(3)),
        ("other: ours", "other|y", fixed(3)), ("LAMMPS", "other|l", fixed(3))]),
    "impact_budget": dict(csv="impact_budget.csv", rows=_impact_budget, columns=[
        ("part of the default impact", "part", text), ("-j1 [s]", "s1", text), ("-j1 µs/step", "us1", text), ("share at -j1", "share1", text),
        ("-j2 [s]", "s2", text), ("-j2 µs/step", "us2", text), ("two threads' speed-up", "speedup", text)]),
    "time_to_result": dict(csv="time_to_result.csv", rows=_time_to_result, columns=[
        ("stage", "stage", text), ("before [s]", "before_s", fixed(1)), ("after [s]", "after_s", fixed(1)), ("speed-up", "speedup", times(2))]),
    "cylinders_timing": dict(csv="cylinders_timing.csv", columns=[
        ("scene", "scene", scene), ("-j", "threads", text), ("built-in µs/step", "builtin_us_per_step", fixed(1)),
        ("yade-flex µs/step", "flex_us_per_step", fixed(1)), ("per step", "speedup_per_step", times(2)),
        ("per simulated second", "speedup_per_simulated_second", times(1))]),
    "cylinders_cantilever": dict(csv="cylinders_cantilever.csv", rows=_cantilever, columns=[
        ("load", "load", text), ("segments", "segments", text), ("built-in", "builtin", fixed(5)), ("yade-flex", "flex", fixed(6))]),
    "facets_timing": dict(csv="facets_timing.csv", columns=[
        ("scene", "scene", scene), ("facets", "facets", text), ("built-in us/step", "builtin_us", lambda v: f"{float(v):.0f}"),
        ("yade-flex us/step", "ours_us", fixed(1)), ("per step", "speedup", times(1)), ("per simulated second", "per_sim_second", times(1))]),
}


def table(name, results=os.path.join(HERE, "results")):
    """The markdown lines of table `name` from its CSV."""
    spec = TABLES[name]
    with open(os.path.join(results, spec["csv"]), newline="") as f:
        rows = list(csv.DictReader(f))
    rows = spec.get("rows", lambda r: r)(rows)
    cols = spec["columns"]
    out = ["| " + " | ".join(h for h, _, _ in cols) + " |", "|" + "---|" * len(cols)]
    out += ["| " + " | ".join(fmt(r[k]) for _, k, fmt in cols) + " |" for r in rows]
    return out


def regenerate(readme_text, results=os.path.join(HERE, "results")):
    """readme_text with every marked block replaced by its table; returns (text, names changed).
    A marker whose name TABLES does not know, or a block without its end marker, raises ValueError."""
    changed = []

    def sub(m):
        name = m.group(1)
        if name not in TABLES:
            raise ValueError(f"bench/README.md: no table named {name!r} in bench/tables.py (known: {', '.join(TABLES)})")
        new = "\n".join(table(name, results))
        if m.group(2).strip("\n") != new:
            changed.append(name)
        return f"<!-- table:{name} -->\n{new}\n<!-- /table:{name} -->"

    text = re.sub(r"<!-- table:([\w.-]+) -->\n(.*?)<!-- /table:\1 -->", sub, readme_text, flags=re.S)
    opened = set(re.findall(r"<!-- table:([\w.-]+) -->", readme_text))
    closed = set(re.findall(r"<!-- /table:([\w.-]+) -->", readme_text))
    if opened != closed:
        raise ValueError(f"bench/README.md: table markers without their pair: {', '.join(sorted(opened ^ closed))}")
    return text, changed


def main():
    ap = argparse.ArgumentParser(description="Regenerate the CSV tables of bench/README.md.")
    ap.add_argument("--check", action="store_true", help="only check: exit 1 if a table differs from its CSV")
    ap.add_argument("--readme", default=os.path.join(HERE, "README.md"))
    a = ap.parse_args()
    with open(a.readme) as f:
        old = f.read()
    new, changed = regenerate(old)
    if a.check:
        if changed:
            print(f"tables differing from their CSV: {', '.join(changed)} (python3 bench/tables.py rewrites them)")
            sys.exit(1)
        print("every marked table matches its CSV")
        return
    if new != old:
        with open(a.readme, "w") as f:
            f.write(new)
    print(f"regenerated: {', '.join(changed) or 'nothing changed'}")


if __name__ == "__main__":
    main()
