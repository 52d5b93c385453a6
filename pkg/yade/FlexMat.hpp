// yade-flex adapter (GPL-2.0-or-later): the material of deformable elements (FrictMat + beam, bond and wire-law
// parameters).
#pragma once
#include "FlexPch.hpp"

namespace yade {

class FlexMat : public FrictMat {
public:
	virtual ~FlexMat() = default;
	/// Whether the axial law is the chain-link wire law (pkg/kernel/WireLaw.hpp).
	bool isWire() const { return !wireStrain.empty() || !wireStress.empty(); }
	/// Empty if the wire parameters are valid (or unused), else what is wrong with them.
	std::string wireError() const;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexMat, FrictMat,
		"Material of deformable elements (yade-flex). ``young`` is Young's modulus of the element and also enters the contact stiffness; ``poisson`` keeps FrictMat's meaning (ks/kn of contacts); the beam's shear modulus uses :yref:`FlexMat.beamPoisson`.",
		((Real, elementYoung, NaN, , "Young's modulus of the element (beam, bar) if it differs from the contact modulus ``young`` [Pa]; NaN: ``young``. A contact modulus below the material's (common DEM practice for steel wires) lengthens the time step without changing the structure's stiffness."))
		((Real, beamPoisson, 0.3, , "Poisson ratio of the element material for G = E/(2(1+nu)) [-]"))
		((Real, bendingFactor, 1.0, , "Scale of bending and torsion stiffness relative to a solid bar [-] (ropes: well below 1; 0: an axial-only bar, no moments, the element loop skips the rotations)"))
		((bool, tensionOnly, false, , "Bonds carry no compression (ropes, wires) [-]"))
		((Real, yieldStress, std::numeric_limits<Real>::infinity(), , "Axial yield stress [Pa]; plastic elongation beyond it"))
		((Real, hardening, 0.0, , "Post-yield axial stiffness as a fraction of EA [-]"))
		((Real, tensileStrength, std::numeric_limits<Real>::infinity(), , "Bond breaks when the axial stress reaches it [Pa]"))
		((Real, ruptureStrain, std::numeric_limits<Real>::infinity(), , "Bond breaks at this total axial strain [-]"))
		((vector<Real>, wireStrain, , , "Chain-link wire law (pkg/kernel/WireLaw.hpp): strains of the stress-strain points, strictly increasing, > 0; the origin is implied [-]. Non-empty: the axial law is the wire law (tension only, elastic unloading with wireStress[0]/wireStrain[0], rupture past the last point); yieldStress, hardening, tensileStrength and ruptureStrain must stay unset. Never modified by the simulation."))
		((vector<Real>, wireStress, , , "Stresses of the stress-strain points of the wire law, > 0 [Pa]"))
		((Real, wireSlackScale, 0.0, , "Scale of the stochastic slack strain of each link: slack = wireSlackScale * xi, xi symmetric triangular on [0, 1] (lambda_u of [Thoeni2013]_) [-]; 0: no distortion"))
		((Real, wireForceRatio, 1.0, , "Force ratio of the soft initial branch of a distorted link, in (0, 1] (lambda_F of [Thoeni2013]_) [-]"))
		((int, wireSeed, 12345, , "Seed of the slack draw; each link's draw is a hash of the seed and its two node ids, so it does not depend on thread count, body order at run time or O.reset() [-]")),
		createIndex();,
		.def("wireError", &FlexMat::wireError, "Empty string if the wire-law parameters are valid (or unused), else what is wrong with them.")
	);
	// clang-format on
	REGISTER_CLASS_INDEX(FlexMat, FrictMat);
};
REGISTER_SERIALIZABLE(FlexMat);

} // namespace yade
