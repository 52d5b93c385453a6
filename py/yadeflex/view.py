"""YADE's 3D view for scenes with yade-flex elements (needs a display: not with yade -n).

The drawing itself is done by the Gl1 functors of the plugin (pkg/yade/FlexGl.hpp):
Gl1_FlexCylinder (capsules), Gl1_FlexFacet (membrane triangles), Gl1_FlexNode (off by default),
each in its shape's color unless coloured by force; color_by_part sets those colours.
"""
import math

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FlexNode, Sphere

from . import parts as P


_legend = {}  # part name -> colour, of the last color_by_part (snapshot draws it)


def color_by_part(parts=None):
    """Set every body's shape.color to its part's colour (yadeflex.parts.part_color: mesh blue,
    rings red, rope teal, lining green, slab grey, grains sand, boulder magenta: a clump's member
    spheres; the groups named with yadeflex.parts.name_parts in the colours of PALETTE). parts:
    body id -> part id (default yadeflex.parts.scene_parts()). Returns dict part name -> number
    of bodies coloured; the legend (printed, and drawn by snapshot) lists those parts."""
    table = P.scene_parts() if parts is None else parts
    names = P.part_names()
    count = {}
    for b in O.bodies:
        if b is None or b.shape is None:
            continue
        k = P.part_of(b, table)
        name = names[k] if k < len(names) else P.PARTS[0]
        b.shape.color = Vector3(*P.part_color(name))
        count[name] = count.get(name, 0) + 1
    _legend.clear()
    _legend.update({n: P.part_color(n) for n in names if n in count})
    return count


def legend():
    """The colour legend of the last color_by_part: list of (part name, RGB [0-1])."""
    return [(n, c) for n, c in _legend.items()]


def scene_box():
    """Axis-aligned box around all bodies [m]: nodes and spheres with their radius, other
    bodies by their bound (elements lie between their nodes). Returns (min, max)."""
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for b in O.bodies:
        if b is None:
            continue
        if isinstance(b.shape, (FlexNode, Sphere)) and math.isfinite(b.shape.radius):
            r = b.shape.radius
            pts = (b.state.pos - Vector3(r, r, r), b.state.pos + Vector3(r, r, r))
        elif b.bound is not None:
            pts = (b.bound.min, b.bound.max)
        else:
            pts = (b.state.pos,)
        for p in pts:
            for k in range(3):
                if math.isfinite(p[k]):
                    lo[k], hi[k] = min(lo[k], p[k]), max(hi[k], p[k])
    if not all(math.isfinite(v) for v in lo + hi):
        raise ValueError("the scene has no body with a finite position to show")
    return Vector3(*lo), Vector3(*hi)


def view(color_by_force=False, show_nodes=False, direction=(0, 1, -0.5), up=(0, 0, 1), color_parts=True, size=None):
    """Open YADE's 3D view (or take the one open) on the whole scene and return it.

    color_parts: colour every body by its part first (color_by_part; False keeps the shapes'
    colours). color_by_force: colour cylinders by axial force and facets by n1 instead (blue:
    compression, grey: zero, red: tension; range +- the largest value in the scene, or set
    Gl1_FlexCylinder.forceRange / Gl1_FlexFacet.forceRange); the other bodies keep their part
    colours. show_nodes: draw the nodes as spheres of their radius. direction, up: viewing
    direction and the direction shown up. size: (width, height) of the view [pixels]. The
    colour legend is printed (and drawn by snapshot)."""
    if size is not None:
        if not (isinstance(size, (tuple, list)) and len(size) == 2 and all(isinstance(x, int) and 16 <= x <= 8192 for x in size)):
            raise ValueError(f"view size: (width, height) in pixels, each 16 to 8192, got {size!r}")
    try:
        from yade import qt
    except ImportError as e:
        raise RuntimeError("yadeflex.view needs YADE's Qt GUI: run yade without -n, on a display (or under xvfb-run)") from e
    from yade.wrapper import Gl1_FlexCylinder, Gl1_FlexFacet, Gl1_FlexNode  # here: the package imports with an older plugin

    if color_parts:
        count = color_by_part()
        print("colours: " + ", ".join(f"{n} ({count[n]})" for n, _ in legend()), flush=True)
    Gl1_FlexCylinder.colorByForce = Gl1_FlexFacet.colorByForce = bool(color_by_force)
    Gl1_FlexNode.show = bool(show_nodes)
    v = qt.views()[0] if qt.views() else qt.View()
    if size is not None:
        _widget().resize(*size)
    v.upVector = Vector3(*up)  # first: setting it turns the camera square to it
    v.viewDir = Vector3(*direction)
    # the sphere around the whole box (GLViewer.fitAABB fits the sphere of its largest side only,
    # and the clipping planes follow the scene radius)
    lo, hi = scene_box()
    qt.center(suggestedRadius=max(0.5 * (hi - lo).norm(), 1e-6), suggestedCenter=0.5 * (lo + hi))
    return v


def _widget():
    """The open 3D view's Qt widget."""
    try:
        from PyQt5.QtWidgets import QApplication
    except ImportError as e:
        raise RuntimeError("yadeflex.snapshot needs YADE's Qt GUI (PyQt5)") from e
    app = QApplication.instance()
    widgets = [w for w in app.topLevelWidgets() if w.metaObject().className() == "yade::GLViewer"] if app else []
    if not widgets:
        raise RuntimeError("no 3D view is open: call yadeflex.view() first (and run yade without -n)")
    app.processEvents()
    return widgets[0]


def _draw_legend(image):
    """The legend (legend()) in the image's top left corner: a swatch and the name of each part."""
    from PyQt5.QtGui import QColor, QFont, QPainter
    entries = legend()
    if not entries:
        return
    p = QPainter(image)
    font = QFont()
    font.setPixelSize(max(11, image.height() // 45))
    p.setFont(font)
    h = font.pixelSize() + 6
    width = 2 * h + max(p.fontMetrics().horizontalAdvance(n) for n, _ in entries) + 8
    p.fillRect(4, 4, width, h * len(entries) + 8, QColor(255, 255, 255, 200))
    for k, (name, c) in enumerate(entries):
        y = 8 + k * h
        p.fillRect(10, y + 2, h - 4, h - 4, QColor(*(int(255 * x) for x in c)))
        p.setPen(QColor(0, 0, 0))
        p.drawText(10 + h + 2, y + h - 5, name)
    p.end()


def snapshot(path, legend=True):
    """Render the open 3D view now and save it to path (format from the suffix: .png is
    lossless), with the colour legend of its parts unless legend is False. Works in scripts
    (yade -x) where no Qt event loop runs; YADE's own GLViewer.saveSnapshot waits for the next
    repaint and writes JPEG whatever the suffix. Returns path."""
    image = _widget().grabFramebuffer()
    if legend and not image.isNull():
        _draw_legend(image)
    if image.isNull() or not image.save(str(path)):
        raise RuntimeError(f"could not save the 3D view to {path}")
    return path
