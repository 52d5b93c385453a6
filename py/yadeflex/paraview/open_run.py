"""Open a yade-flex run in ParaView with sensible defaults; render frames to PNG offscreen.

Run by pvpython (Debian package paraview), from a shell:

    pvpython py/yadeflex/paraview/open_run.py RUN --png peak.png          # the frame at peak force
    pvpython py/yadeflex/paraview/open_run.py RUN --png f.png --time 0.004 --color part --clip
    pvpython py/yadeflex/paraview/open_run.py RUN --frames DIR --clip      # every frame: DIR/frame_NNNN.png

(on a machine without a display: xvfb-run -a pvpython ..., or yadeflex.paraview.run_open_run,
which starts a virtual display of its own). RUN is a results folder of the main
job (its vtk/flex.pvd; timeseries.csv and summary.json for --time peak) or a .pvd file. In the
ParaView GUI: View > Python Shell > Run Script, then open_run("RUN") in the shell.

What is shown (yadeflex/vtk_frames.py describes the files; yadeflex/parts.py the parts):
- wires (mesh legs, rings, rope) as tubes, coloured by axial force [N] (--color force, the
  default; cool to warm, symmetric about 0) or in their part's colour (--color part); broken
  elements are left out;
- the lining as its triangles, coloured by the membrane force n1 [N/m] or in its part's colour;
- the grains as spheres of their radius (Glyph), the boulder as its hull (the clumps group);
- the contacts as force chains: black tubes between the contacting bodies' centres, their
  radius growing with the contact force [N] from CONTACT_TUBE / 4 at the smallest force of the
  frame to CONTACT_TUBE at the largest (--no-contacts leaves them out); grains are drawn at
  GRAIN_SCALE_WITH_CONTACTS of their size while they are shown;
- --clip: everything cut by the plane y = the boulder's y, the front half removed, to see inside;
  the grains and contacts only in a slab SLAB deep behind the cut (a section through the fill).
Filters: each group is ExtractBlock > ExtractSurface first (Cell Data to Point Data straight on
the reader's blocks crashes pvpython 5.11), then CellDatatoPointData > Tube for lines.
"""
import argparse
import csv
import importlib.util
import json
import math
import os
import sys

from paraview import simple as pv

# (ParaView's Run Script may leave __file__ unset: YADEFLEX_PY names the package's folder then)
HERE = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.path.join(os.environ.get("YADEFLEX_PY", "py"), "yadeflex", "paraview")
_spec = importlib.util.spec_from_file_location("yadeflex_parts", os.path.join(os.path.dirname(HERE), "parts.py"))
PARTS_MODULE = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(PARTS_MODULE)
PART = PARTS_MODULE.PART

BACKGROUND = (1.0, 1.0, 1.0)
GRAIN_SCALE_WITH_CONTACTS = 0.5  # grains drawn at this fraction of their size while force chains are shown
SLAB = 0.08  # [m] with --clip, grains and contacts are shown in this slab behind the cut only (a section)
CONTACT_TUBE = 0.006  # [m] force-chain tube radius at the largest force of the frame shown
CONTACT_COLOR = (0.05, 0.05, 0.05)  # force chains: black, their thickness gives the force
WIRE_TUBE_MIN = 0.002  # [m] wires thinner than this are drawn this thick (a 1.5 mm wire is sub-pixel)


def pvd_of(run):
    """The .pvd of a results folder (RUN/vtk/flex.pvd) or the .pvd given."""
    if run.endswith(".pvd"):
        path = run
    else:
        path = os.path.join(run, "vtk", "flex.pvd")
    if not os.path.isfile(path):
        raise ValueError(f"no VTK series at {path}: give a results folder with vtk/flex.pvd, or a .pvd file")
    return path


def peak_time(run):
    """Series time [s] (from the first contact) of the peak impact force of a results folder:
    timeseries.csv's t at the largest impact_force, less summary.json's free_fall_check.t."""
    with open(os.path.join(run, "timeseries.csv"), newline="") as fh:
        rows = list(csv.DictReader(fh))
    key = lambda name: next(k for k in rows[0] if k == name or k.startswith(name + "["))
    tk, fk = key("t"), key("impact_force")
    best = max(rows, key=lambda r: float(r[fk]))
    with open(os.path.join(run, "summary.json")) as fh:
        ff = json.load(fh).get("free_fall_check") or {}
    return float(best[tk]) - float(ff.get("t", 0.0))


def part_names(pvd):
    """The name of each part id of a series: its PREFIX_parts.json beside the .pvd (written by
    yadeflex.vtk_frames), else the standard parts."""
    path = pvd[:-len(".pvd")] + "_parts.json"
    if os.path.isfile(path):
        with open(path) as fh:
            return json.load(fh)
    return list(PARTS_MODULE.PARTS)


def _groups(reader):
    """Names of the blocks of the series (the .pvd's DataSet names)."""
    import xml.etree.ElementTree as ET
    root = ET.parse(reader.FileName).getroot()
    return {d.get("name") for d in root.iter("DataSet")}


def _threshold(src, array, lo, hi, points=False):
    th = pv.Threshold(Input=src)
    th.Scalars = ["POINTS" if points else "CELLS", array]
    # after Scalars: setting it resets the bounds to the array's range
    th.ThresholdMethod = "Between"
    th.LowerThreshold, th.UpperThreshold = lo, hi
    return pv.ExtractSurface(Input=th)


def _slab(src, origin):
    """src between the cut plane and SLAB behind it (whole cells), or src without a cut."""
    if origin is None:
        return src
    behind = [origin[0], origin[1] + SLAB, origin[2]]
    c = pv.Clip(Input=_clip(src, origin), ClipType="Plane", Crinkleclip=1)
    c.ClipType.Origin = behind
    c.ClipType.Normal = [0.0, 1.0, 0.0]
    c.Invert = 1  # keeps y <= origin's + SLAB
    return c


def _clip(src, origin, crinkle=1):
    """src cut by the plane y = origin's y, the front (y < origin's) removed; crinkle: whole cells
    (whole tubes, spheres, triangles) kept."""
    if origin is None:
        return src
    c = pv.Clip(Input=src, ClipType="Plane", Crinkleclip=crinkle)
    c.ClipType.Origin = origin
    c.ClipType.Normal = [0.0, 1.0, 0.0]
    c.Invert = 0  # keeps y >= origin: the back half, seen from -y
    return c


def _solid(view, src, color, opacity=1.0):
    d = pv.Show(src, view)
    d.ColorArrayName = [None, ""]
    d.AmbientColor = d.DiffuseColor = list(color)
    d.Opacity = opacity
    return d


def _by(view, src, assoc, array, preset, symmetric, bar_title, bar=True):
    d = pv.Show(src, view)
    pv.ColorBy(d, (assoc, array))
    lut = pv.GetColorTransferFunction(array)
    lut.ApplyPreset(preset, True)
    d.RescaleTransferFunctionToDataRange(False, True)
    lo, hi = lut.RGBPoints[0], lut.RGBPoints[-4]
    if symmetric:
        m = max(abs(lo), abs(hi), 1e-12)
        lut.RescaleTransferFunction(-m, m)
    lut.AutomaticRescaleRangeMode = "Never"
    if bar:
        d.SetScalarBarVisibility(view, True)
        sb = pv.GetScalarBar(lut, view)
        sb.Title, sb.ComponentTitle = bar_title, ""
        sb.TitleColor = sb.LabelColor = [0.1, 0.1, 0.1]
        sb.TitleFontSize = sb.LabelFontSize = 12
    return d


def open_run(run, time="peak", color="force", clip=False, contacts=True, size=(1200, 900), view=None):
    """Build the pipeline of a run (results folder or .pvd) in a render view at `time` (series
    time [s], or 'peak', 'first', 'last'; 'peak' needs a results folder). Returns dict(view,
    reader, time, displays: name -> display)."""
    if color not in ("force", "part"):
        raise ValueError(f"color must be 'force' or 'part', got {color!r}")
    pvd = pvd_of(run)
    reader = pv.PVDReader(FileName=pvd)
    times = list(reader.TimestepValues) or [0.0]
    if time == "peak":
        if run.endswith(".pvd"):
            raise ValueError("time 'peak' needs the results folder (its timeseries.csv), not a .pvd")
        want = peak_time(run)
    elif time == "first":
        want = times[0]
    elif time == "last":
        want = times[-1]
    else:
        want = float(time)
    t = min(times, key=lambda x: abs(x - want))
    view = view or pv.GetActiveViewOrCreate("RenderView")  # (in the GUI: the open view)
    view.ViewSize = list(size)
    view.Background = list(BACKGROUND)
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesVisibility = 0
    view.ViewTime = t
    groups = _groups(reader)
    reader.UpdatePipeline(t)
    origin = None
    if clip:
        origin = [0.0, 0.0, 0.0]
        if "clumps" in groups:
            b = pv.ExtractBlock(Input=reader, Selectors=["/Root/clumps"])
            b.UpdatePipeline(t)
            bb = b.GetDataInformation().GetBounds()
            if bb[0] <= bb[1]:
                origin = [0.5 * (bb[0] + bb[1]), 0.5 * (bb[2] + bb[3]), 0.5 * (bb[4] + bb[5])]
    shown = {}
    names = part_names(pvd)
    part_col = lambda name: PARTS_MODULE.color_of(name, names)
    named = [n for n in names if n not in PART]  # the groups the scene named (yadeflex.parts.name_parts)
    if "cylinders" in groups:
        cyl = pv.ExtractSurface(Input=pv.ExtractBlock(Input=reader, Selectors=["/Root/cylinders"]))
        intact = _threshold(cyl, "broken", 0, 0)
        for name in ["mesh", "ring", "rope", "other"] + named:
            k = names.index(name)
            sel = _threshold(intact, "part", k, k)
            sel.UpdatePipeline(t)
            if sel.GetDataInformation().GetNumberOfCells() == 0:
                continue
            r = sel.GetDataInformation().GetCellDataInformation().GetArrayInformation("radius").GetComponentRange(0)[1]
            tube = pv.Tube(Input=pv.CellDatatoPointData(Input=sel), Radius=max(r, WIRE_TUBE_MIN), NumberofSides=8)
            tube = _clip(tube, origin)
            if color == "part":
                shown[name] = _solid(view, tube, part_col(name))
            else:
                shown[name] = _by(view, tube, "POINTS", "axialForce", "Cool to Warm", True, "axial force [N]", bar=(name == "mesh"))
    if "facets" in groups:
        fac = _threshold(pv.ExtractSurface(Input=pv.ExtractBlock(Input=reader, Selectors=["/Root/facets"])), "broken", 0, 0)
        fac = _clip(fac, origin)
        if color == "part":
            shown["lining"] = _solid(view, fac, part_col("lining"))
        else:
            shown["lining"] = _by(view, fac, "CELLS", "n1", "Viridis (matplotlib)", False, "lining n1 [N/m]")
    if "spheres" in groups:
        sph = pv.ExtractSurface(Input=pv.ExtractBlock(Input=reader, Selectors=["/Root/spheres"]))
        chains = contacts and "contacts" in groups
        for name in ["grain"] + named:
            k = names.index(name)
            grains = _threshold(sph, "part", k, k, points=True)
            if name != "grain":
                grains.UpdatePipeline(t)
                if grains.GetDataInformation().GetNumberOfPoints() == 0:
                    continue
            g = pv.Glyph(Input=grains, GlyphType="Sphere", ScaleArray=["POINTS", "radius"], GlyphMode="All Points")
            g.ScaleFactor = 2.0 * (GRAIN_SCALE_WITH_CONTACTS if chains else 1.0)  # after ScaleArray, which resets it
            g.GlyphType.ThetaResolution = 16
            g.GlyphType.PhiResolution = 12
            shown[name] = _solid(view, _slab(g, origin), part_col(name))
    if "clumps" in groups:
        hull = pv.ExtractSurface(Input=pv.ExtractBlock(Input=reader, Selectors=["/Root/clumps"]))
        shown["boulder"] = _solid(view, _clip(hull, origin, crinkle=0), part_col("boulder"))
    if contacts and "contacts" in groups:
        con = pv.ExtractSurface(Input=pv.ExtractBlock(Input=reader, Selectors=["/Root/contacts"]))
        con.UpdatePipeline(t)
        fmax = con.GetDataInformation().GetCellDataInformation().GetArrayInformation("force")
        fmax = fmax.GetComponentRange(0)[1] if fmax is not None else 0.0
        if fmax > 0:
            # radius from CONTACT_TUBE / 4 at the smallest force to CONTACT_TUBE at the largest
            tube = pv.Tube(Input=pv.CellDatatoPointData(Input=con), Scalars=["POINTS", "force"], VaryRadius="By Scalar",
                           Radius=0.25 * CONTACT_TUBE, RadiusFactor=4.0, NumberofSides=6)
            shown["contacts"] = _solid(view, _slab(tube, origin), CONTACT_COLOR)
    # camera: from -y, a little above, the whole scene in view
    pv.SetActiveView(view)
    # (cut: nearly head-on, to look at the section)
    view.CameraPosition = [0.0, -4.0, 0.8 if clip else 3.0]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    view.CameraParallelProjection = 0
    pv.GetActiveCamera().Zoom(1.15)
    return dict(view=view, reader=reader, time=t, displays=shown, times=times)


def render(run, png, **kw):
    """open_run(run, **kw) and save the view to png. Returns the series time shown [s]."""
    r = open_run(run, **kw)
    pv.Render(r["view"])
    pv.SaveScreenshot(png, r["view"], ImageResolution=list(r["view"].ViewSize), TransparentBackground=0)
    return r["time"]


def render_frames(run, folder, **kw):
    """Every frame of the series into folder/frame_NNNN.png (for a movie), the colour ranges
    those of the peak force's frame (a results folder) or of the last frame. Returns the count."""
    os.makedirs(folder, exist_ok=True)
    r = open_run(run, time="last" if run.endswith(".pvd") else "peak", **kw)
    for k, t in enumerate(r["times"]):
        r["view"].ViewTime = t
        pv.Render(r["view"])
        pv.SaveScreenshot(os.path.join(folder, f"frame_{k:04d}.png"), r["view"], ImageResolution=list(r["view"].ViewSize),
                          TransparentBackground=0)
    return len(r["times"])


def main(argv):
    ap = argparse.ArgumentParser(prog="open_run.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="results folder (with vtk/flex.pvd) or a .pvd file")
    ap.add_argument("--png", help="render the frame at --time to this PNG and exit")
    ap.add_argument("--frames", help="render every frame to FOLDER/frame_NNNN.png and exit")
    ap.add_argument("--time", default=None, help="series time [s] from the first contact, or peak (default with a results folder), first, last")
    ap.add_argument("--color", default="force", choices=("force", "part"))
    ap.add_argument("--clip", action="store_true", help="cut away the front half (y < the boulder's y)")
    ap.add_argument("--no-contacts", action="store_true")
    ap.add_argument("--size", nargs=2, type=int, default=(1200, 900), metavar=("W", "H"))
    a = ap.parse_args(argv)
    time = a.time or ("last" if a.run.endswith(".pvd") else "peak")
    kw = dict(color=a.color, clip=a.clip, contacts=not a.no_contacts, size=tuple(a.size))
    try:
        if a.frames:
            n = render_frames(a.run, a.frames, **kw)
            print(f"{n} frames in {a.frames}")
        elif a.png:
            t = render(a.run, a.png, time=time, **kw)
            print(f"{a.png}: t = {1e3 * t:.2f} ms after the first contact")
        else:
            open_run(a.run, time=time, **kw)
            pv.Render()
    except ValueError as e:
        print(f"open_run.py: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__" and len(sys.argv) > 1:
    status = main(sys.argv[1:])
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)  # pvpython 5.11 under Xvfb fails in its teardown (GLXBadContext) after the work is done
