"""Mass scaling of light nodes (yadeflex.mass_scaling) on any membrane or mesh, and the fill
helpers taking any form of a fill preset (yadeflex.module.fill.fill_preset)."""
import pytest
from yade import O

import yadeflex as yf
from yadeflex.checks import BadValue
from yadeflex.grains import FILLS, fill_engines, fill_preset
from yadeflex.mass_scaling import scale_node_masses
from yadeflex.module import ModuleParams, scale_lining_nodes
from yadeflex.harness.scenes import sphere


def test_light_nodes_of_a_sheet_get_the_mass_asked_their_inertia_scaled_alike(scene):
    """A 4 x 4 geotextile sheet (border fixed): every free node below m_min ends at m_min exactly,
    its inertia scaled by the same factor; fixed nodes keep theirs; the sums returned are the mass
    added and the free nodes' own mass; m_min = 0 changes nothing."""
    s = yf.sheet(4, 4, (0.4, 0.4), 0.002, yf.geotextile())
    nodes = sorted({n for row in s["grid"] for n in row})
    before = {n: (O.bodies[n].state.mass, tuple(O.bodies[n].state.inertia), O.bodies[n].dynamic) for n in nodes}
    free = [n for n in nodes if before[n][2]]
    assert free and len(free) < len(nodes)
    assert scale_node_masses(nodes, 0.0) == (0.0, pytest.approx(sum(before[n][0] for n in free), rel=1e-15))
    m_min = 3 * max(before[n][0] for n in nodes)
    added, own = scale_node_masses(nodes, m_min)
    assert own == pytest.approx(sum(before[n][0] for n in free), rel=1e-15)
    assert added == pytest.approx(sum(m_min - before[n][0] for n in free), rel=1e-15)
    for n in nodes:
        st, (m0, i0, dyn) = O.bodies[n].state, before[n]
        if dyn:
            assert st.mass == m_min
            assert tuple(st.inertia) == pytest.approx(tuple(x * m_min / m0 for x in i0), rel=1e-15)
        else:
            assert (st.mass, tuple(st.inertia)) == (m0, i0)


def test_bad_nodes_and_masses_are_refused_by_name(scene):
    s = yf.sheet(2, 2, (0.2, 0.2), 0.002, yf.geotextile())
    ball = sphere((1, 0, 0), 0.01)
    nodes = sorted({n for row in s["grid"] for n in row})
    with pytest.raises(BadValue, match=r"FlexNode bodies \(body #%d is a Sphere\)" % ball):
        scale_node_masses(nodes + [ball], 0.02)
    with pytest.raises(BadValue, match="m_min"):
        scale_node_masses(nodes, -1.0)
    with pytest.raises(BadValue, match="m_min"):
        scale_node_masses(nodes, float("nan"))
    with pytest.raises(BadValue, match="ids of existing bodies"):
        scale_node_masses([len(O.bodies) + 5], 0.02)
    # the module's helper takes the module's ids, and says so
    with pytest.raises(TypeError, match="no 'modules' key"):
        scale_lining_nodes({"lining_nodes": nodes}, 0.02)


def test_a_fill_preset_is_taken_in_any_of_its_forms(scene):
    p = ModuleParams(fill="sand", grain_max=0.028)
    assert fill_preset(p) == p.preset() and fill_preset(p)["grain_max"] == 0.028
    assert fill_preset("gravel") == FILLS["gravel"] and fill_preset("gravel") is not FILLS["gravel"]
    assert fill_preset(FILLS["sand"]) is FILLS["sand"]
    with pytest.raises(BadValue, match="missing density, friction_deg"):
        fill_preset(dict(grain_min=0.02, grain_max=0.03, young=1e8, rolling_friction=0.1))
    with pytest.raises(BadValue, match="fill"):
        fill_preset("basalt")
    with pytest.raises(BadValue, match="a ModuleParams, the name of a preset"):
        fill_preset(0.05)
    # fill_engines from the parameters, as from their preset: the same rolling resistance
    law = lambda engines: next(f for e in engines if hasattr(e, "lawDispatcher") for f in e.lawDispatcher.functors if hasattr(f, "rollingFriction"))
    assert law(fill_engines(p, 0.3)).rollingFriction == law(fill_engines(p.preset(), 0.3)).rollingFriction == FILLS["sand"]["rolling_friction"]
