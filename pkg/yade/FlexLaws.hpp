// yade-flex adapter: the kernel's element laws and sections from the materials
// (GPL-2.0-or-later).
#pragma once
#include "Flex.hpp"
#include "FlexFacet.hpp"

#include <kernel/Beam.hpp>
#include <kernel/Membrane.hpp>

#include <cmath>

namespace yade {
namespace flexa {
	/// The circular section of a wire of this radius: FlexMat.elementYoung (else young), shear
	/// modulus from beamPoisson, bending scaled by bendingFactor.
	inline flex::BeamSection section(const FlexMat& m, Real radius)
	{
		const Real E = std::isfinite(m.elementYoung) ? m.elementYoung : m.young;
		return flex::BeamSection::circular(E, E / (2 * (1 + m.beamPoisson)), radius, m.bendingFactor);
	}
	inline flex::AxialLaw axialLaw(const FlexMat& m, Real radius)
	{
		const Real     A = M_PI * radius * radius;
		flex::AxialLaw law;
		law.tensionOnly   = m.tensionOnly;
		law.yieldForce    = m.yieldStress * A;
		law.hardening     = m.hardening;
		law.ruptureForce  = m.tensileStrength * A;
		law.ruptureStrain = m.ruptureStrain;
		return law;
	}
	inline flex::MembraneLaw membraneLaw(const FlexMembraneMat& m)
	{
		flex::MembraneLaw law;
		law.Et          = m.stiffness;
		law.nu          = m.membranePoisson;
		law.tensionOnly = m.tensionOnly;
		law.strength    = m.strength;
		return law;
	}
	/// Rest state of a facet from its stored rest shape.
	inline flex::MembraneRest membraneRest(const FlexFacet& f)
	{
		flex::MembraneRest r;
		r.A0 = f.area0;
		Eigen::Matrix2d Dm;
		Dm << f.restEdges[0], f.restEdges[1], 0, f.restEdges[2];
		r.DmInv = Dm.inverse();
		return r;
	}
} // namespace flexa
} // namespace yade
