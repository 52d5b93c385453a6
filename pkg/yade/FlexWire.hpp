// Chain-link wire law in the element loop (GPL-2.0-or-later): unpack, call the kernel
// (pkg/kernel/WireLaw.hpp), write the named state back. Not part of the Python API.
#pragma once
#include "Flex.hpp"

#include <kernel/Beam.hpp>
#include <kernel/WireLaw.hpp>

#include <stdexcept>

namespace yade {
namespace flexa {
	/// Axial response of wire element c at axial strain `strain`; updates c.maxStrain and
	/// c.plasticStrain. The material's curve is read, never written.
	/// The elastic modulus of m's wire curve (stress[0] / strain[0]) [Pa], for wireAxial.
	inline Real wireModulus(const FlexMat& m)
	{
		return flex::WireCurve { m.wireStrain.data(), m.wireStress.data(), (int)m.wireStrain.size() }.elasticModulus();
	}
	/// Ew: wireModulus(m) if the caller has it (the same value, one division less per link and
	/// step), else 0.
	inline flex::AxialResult wireAxial(const FlexMat& m, FlexCylinder& c, Real strain, Real Ew = 0)
	{
		const flex::WireCurve curve { m.wireStrain.data(), m.wireStress.data(), (int)m.wireStrain.size(), Ew };
		flex::WireState       st { c.maxStrain, c.plasticStrain };
		const flex::WireAxial a = flex::wireAxial(strain, c.L0, M_PI * c.radius * c.radius, curve, { c.wireSlack, m.wireForceRatio }, st);
		c.maxStrain             = st.maxStrain;
		c.plasticStrain         = st.plasticStrain;
		flex::AxialResult r;
		r.N             = a.N;
		r.elasticEnergy = a.elasticEnergy;
		r.plasticWork   = a.plasticWork;
		r.rupture       = a.rupture;
		return r;
	}
	/// Throws std::invalid_argument naming the material if a wire material of the scene was
	/// made invalid after its elements were attached (checked before the element loop: a
	/// throw inside the OpenMP loop would abort YADE).
	inline void checkWireMaterials(const Scene* scene)
	{
		for (const auto& mat : scene->materials) {
			const FlexMat* m = dynamic_cast<const FlexMat*>(mat.get());
			if (!m) continue;
			const std::string e = m->wireError();
			if (!e.empty()) throw std::invalid_argument("FlexMat '" + m->label + "': " + e);
		}
	}
} // namespace flexa
} // namespace yade
