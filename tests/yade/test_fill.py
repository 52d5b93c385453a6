"""The module's fill packs densely (yadeflex.module.settle_fill): settled first without friction,
then with it, until at rest. A fill settled with its friction from the start froze in a loose
packing (solid fraction 0.40, 2.3 contacts per grain on the default module) that kept collapsing
under the boulder (bench/fill_equilibrium.py); this test guards the dense procedure on a smaller
container."""
import math
import random

from yade import O

from yadeflex.module import ModuleParams, settle_fill


def _core_fraction(grains, r_in, H, dmax):
    """Solid fraction of the core (radius r_in - dmax, heights dmax .. H - 2 dmax), grains counted
    by their centres: away from the container wall, the floor and the trimmed top, where a
    packing is looser by geometry."""
    rc, z0, z1 = r_in - dmax, dmax, H - 2 * dmax
    v = sum(4 / 3 * math.pi * O.bodies[g].shape.radius ** 3 for g in grains
            if z0 <= O.bodies[g].state.pos[2] <= z1 and math.hypot(O.bodies[g].state.pos[0], O.bodies[g].state.pos[1]) <= rc)
    return v / (math.pi * rc ** 2 * (z1 - z0))


def test_fill_is_dense(scene):
    p = ModuleParams(diameter=0.6, height=0.35)  # gravel, 32-63 mm: about 9 grains across
    r_in = 0.27
    wall, grains, _ = settle_fill(p, r_in, random.Random(1))
    dmax = p.preset()["grain_max"]
    phi = _core_fraction(grains, r_in, p.height, dmax)
    # random packings of spheres: 0.55 (loose, high friction) to 0.64 (dense); a bidisperse
    # range packs a little denser. Measured here: 0.64; the loose procedure (friction from the
    # start) on this same container: 0.51, and 3.3 contacts per grain.
    assert 0.55 < phi < 0.70, phi
    # grain-grain contacts per grain: an isostatic frictional packing has 4 to 6 (the loose fill
    # had 2.3); counted over all kept grains, those at the free top surface included
    gs = set(grains)
    gg = sum(1 for i in O.interactions if i.isReal and i.id1 in gs and i.id2 in gs)
    assert 2 * gg / len(grains) > 3.5, 2 * gg / len(grains)


def test_heavier_nodes_settle_to_the_same_equilibrium_and_are_restored(scene):
    """The structure's settle with mass scaling (yadeflex.module._heavier_nodes): a cantilever
    under its own weight, its nodes 50 x heavier with their weight held at m g, settles to the
    deflection it settles to with its own masses; the masses, inertias and forces come back."""
    from yadeflex.harness import scenes as S
    from yadeflex.module import _heavier_nodes, _restore_nodes

    def tip_deflection(factor):
        s = S.cantilever(segments=4, load="self")
        mass = {n: (O.bodies[n].state.mass, tuple(O.bodies[n].state.inertia)) for n in s["nodes"]}
        heavier = _heavier_nodes(factor)
        assert len(heavier) == (len(s["nodes"]) - 1 if factor > 1 else 0)  # the clamped node is not dynamic
        S.settle([s["tip"]], rel_tol=1e-7)
        _restore_nodes(heavier)
        assert {n: (O.bodies[n].state.mass, tuple(O.bodies[n].state.inertia)) for n in s["nodes"]} == mass
        assert not O.forces.getPermForceUsed()
        return -O.bodies[s["tip"]].state.pos[2]

    own, heavy = tip_deflection(1.0), tip_deflection(50.0)
    assert own > 0
    assert abs(heavy - own) <= 1e-5 * own, (heavy, own)


def test_deposition_friction_leaves_a_looser_fill(scene):
    """fill_deposition_friction_deg: densified at the fill's own friction (38 deg, no rolling
    resistance), the same container packs looser than the dense fill's 0.55-0.70, as a random
    loose packing of frictional spheres does (0.55-0.60), and still carries itself."""
    p = ModuleParams(diameter=0.6, height=0.35, fill_deposition_friction_deg=38.0)
    r_in = 0.27
    wall, grains, _ = settle_fill(p, r_in, random.Random(1))
    phi = _core_fraction(grains, r_in, p.height, p.preset()["grain_max"])
    assert 0.50 < phi < 0.60, phi
    gs = set(grains)
    gg = sum(1 for i in O.interactions if i.isReal and i.id1 in gs and i.id2 in gs)
    assert 2 * gg / len(grains) > 3.0, 2 * gg / len(grains)
