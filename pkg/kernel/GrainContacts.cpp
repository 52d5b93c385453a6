// GrainContacts (GPL-2.0-or-later): see GrainContacts.hpp.
#include "GrainContacts.hpp"

#include "Contact.hpp"
#include "Onset.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flex {

GrainContacts::GrainContacts(const GrainLaw& law) { setLaw(law); }

void GrainContacts::setLaw(const GrainLaw& law)
{
	if (!(law.young > 0) || !std::isfinite(law.young)) throw std::invalid_argument("GrainContacts: young must be finite and positive");
	if (!(law.ksOverKn >= 0) || !std::isfinite(law.ksOverKn)) throw std::invalid_argument("GrainContacts: ksOverKn must be finite and >= 0");
	if (!(law.tanPhi >= 0) || !std::isfinite(law.tanPhi)) throw std::invalid_argument("GrainContacts: tanPhi must be finite and >= 0");
	if (!(law.rollingStiffness >= 0) || !(law.rollingFriction >= 0) || !std::isfinite(law.rollingStiffness) || !std::isfinite(law.rollingFriction))
		throw std::invalid_argument("GrainContacts: rollingStiffness and rollingFriction must be finite and >= 0");
	if (!(law.onsetFactor >= 0)) throw std::invalid_argument("GrainContacts: onsetFactor must be >= 0");
	law_ = law;
}

void GrainContacts::restart(const GrainNeighbours& nb)
{
	first_  = nb.first();
	second_ = nb.second();
	state_.assign(second_.size(), State());
}

GrainContacts::State* GrainContacts::at(long i, int j)
{
	if (i < 0 || i + 1 >= (long)first_.size()) return nullptr;
	const auto b = second_.begin() + first_[i], e = second_.begin() + first_[i + 1];
	const auto k = std::lower_bound(b, e, j);
	return (k != e && *k == j) ? &state_[k - second_.begin()] : nullptr;
}

long GrainContacts::follow(const GrainNeighbours& nb)
{
	const std::vector<long>& f = nb.first();
	const std::vector<int>&  s = nb.second();
	std::vector<State>       next(s.size());
	long                     lost = 0;
	const long               nOld = (long)first_.size() - 1, nNew = (long)f.size() - 1;
	for (long i = 0; i < nOld; ++i) {
		long       k    = i < nNew ? f[i] : 0;
		const long kEnd = i < nNew ? f[i + 1] : 0;
		for (long o = first_[i]; o < first_[i + 1]; ++o) {
			if (!state_[o].exists) continue;
			while (k < kEnd && s[k] < second_[o])
				++k;
			if (k < kEnd && s[k] == second_[o])
				next[k] = state_[o];
			else
				++lost;
		}
	}
	first_  = f;
	second_ = s;
	state_.swap(next);
	return lost;
}

long GrainContacts::contacts() const
{
	long c = 0;
	for (const State& s : state_)
		c += s.exists;
	return c;
}

long GrainContacts::active() const
{
	long c = 0, last = -2;
	for (const State& s : state_)
		last = std::max(last, s.lastActive);
	for (const State& s : state_)
		c += s.exists && s.lastActive == last;
	return c;
}

namespace {
	// One step of the onset and release correction of contact s at overlap d and overlap rate
	// `rate`, its state continued from the last step or started anew (a contact not followed last
	// step): the extra normal force on sphere 2, repulsive positive [N]
	double crossingStepOf(GrainContacts::State& s, long iter, double d, double rate, double dt, double invMass)
	{
		if (s.crossIter != iter - 1) s.cross = crossingStart(s.kn, d, rate, dt);
		s.crossIter = iter;
		return crossingStep(s.cross, s.kn, d, rate, dt, [&] { return invMass; });
	}
} // namespace

long GrainContacts::splitAt(int k, int parts) const
{
	const long n = (long)first_.size() - 1;
	if (k <= 0) return 0;
	if (k >= parts) return n;
	const long target = (long)((double)first_[n] * k / parts);
	return std::lower_bound(first_.begin(), first_.end() - 1, target) - first_.begin();
}

void GrainContacts::step(const GrainMotion& m, long iter, double dt, GrainSums& sums, long begin, long end)
{
	const GrainLaw& L     = law_;
	const long      nList = (long)first_.size() - 1;
	if (nList != m.n) throw std::invalid_argument("GrainContacts::step: the spheres are not those of the list followed");
	if (begin < 0 || end > nList || begin > end) throw std::invalid_argument("GrainContacts::step: a range of spheres outside the list");
	// the sums in locals, added to `sums` once (parts on other threads: their sums may share a
	// cache line with these)
	Vec3* const force   = sums.force;
	Vec3* const torque  = sums.torque;
	double      elastic = 0, friction = 0, rolling = 0, deepEnergy = 0, maxRatio = sums.maxOverlapRatio;
	long        deep = 0, maxI = -1, maxJ = -1, touching = 0;
	for (long i = begin; i < end; ++i) {
		const Vec3&  x1 = m.pos[i];
		const double R1 = m.radius[i];
		for (long k = first_[i]; k < first_[i + 1]; ++k) {
			const int    j  = second_[k];
			State&       s  = state_[k];
			const Vec3&  x2 = m.pos[j];
			const double R2 = m.radius[j];
			// geometry (Ig2_Sphere_Sphere_FlexContactGeom::update)
			const Vec3   d    = x2 - x1;
			const double dist = d.norm(), overlap = R1 + R2 - dist;
			const bool   isNew = !s.exists;
			if (isNew) {
				if (overlap <= 0) continue; // (no contact: nothing to do)
				s        = State();
				s.exists = true;
				// (Ip2_FrictMat_FrictMat_FrictPhys with equal materials)
				L.stiffness(R1, R2, s.kn, s.ks);
			}
			const Vec3 n           = dist > 0 ? Vec3(d / dist) : (isNew ? Vec3(Vec3::UnitZ()) : Vec3(s.normal));
			s.normal               = n;
			const Vec3   c         = x1 + (R1 - 0.5 * overlap) * n;
			const Vec3   v1        = m.vel[i] + m.angVel[i].cross(c - x1);
			const Vec3   v2        = m.vel[j] + m.angVel[j].cross(c - x2);
			const Vec3   relVel    = v2 - v1;
			const bool   own       = overlap > 0;
			const bool   wasActive = s.lastActive == iter - 1;
			const double Reff      = R1 * R2 / (R1 + R2);
			const double kr        = L.rollingStiffness > 0 ? L.rollingStiffness * s.ks * Reff * Reff : 0.0;
			if (!own) {
				// separated: its springs' energy leaves with it; the correction runs on
				if (wasActive && L.trackEnergy && s.ks > 0) {
					friction += 0.5 * s.shear.squaredNorm() / s.ks;
					if (kr > 0) rolling += 0.5 * s.roll.squaredNorm() / kr;
				}
				bool crossingOn = false;
				if (L.crossing && s.crossIter == iter - 1) {
					const double cf = crossingStepOf(s, iter, overlap, -n.dot(relVel), dt, m.invMass[i] + m.invMass[j]);
					if (cf != 0) {
						const Vec3 F = cf * n;
						force[i] -= F;
						torque[i] += (c - x1).cross(Vec3(-F));
						force[j] += F;
						torque[j] += (c - x2).cross(F);
					}
					crossingOn = !crossingDone(s.cross);
				}
				if (!(s.lastActive >= iter - 1 || crossingOn)) s = State(); // (ended)
				continue;
			}
			// (re)starting: no shear, judged as an onset
			const bool   handover   = !wasActive;
			const double onsetDepth = handover ? overlap : 0.0;
			s.lastActive            = iter;
			++touching;
			if (onsetDepth > 0) {
				const double approach = std::max(0.0, -n.dot(relVel)) * dt;
				if (onsetDepth > L.onsetFactor * approach) {
					++deep;
					deepEnergy += normalSpring(s.kn, onsetDepth, 0, false).energy;
				}
			}
			if (overlap / (R1 + R2) > maxRatio) {
				maxRatio = overlap / (R1 + R2);
				maxI     = i;
				maxJ     = j;
			}
			const Vec3              shear = rotateShear(handover ? Vec3(Vec3::Zero()) : s.shear, n);
			const Vec3              dus   = (relVel - n.dot(relVel) * n) * dt;
			const FrictionalContact fc { s.kn, s.ks, L.tanPhi };
			const NormalSpring      spring = normalSpring(s.kn, overlap, 0, false);
			const FrictionalResult  r      = frictionalStepWithNormal(fc, spring.force, n, shear, dus);
			s.shear                        = r.shearForce;
			const double cross             = L.crossing ? crossingStepOf(s, iter, overlap, -n.dot(relVel), dt, m.invMass[i] + m.invMass[j]) : 0.0;
			const Vec3   F                 = r.normalForce + r.shearForce + cross * n; // on sphere 2
			force[i] -= F;
			torque[i] += (c - x1).cross(Vec3(-F));
			force[j] += F;
			torque[j] += (c - x2).cross(F);
			double rollEnergy = 0;
			if (kr > 0) {
				const Vec3         dw  = m.angVel[j] - m.angVel[i];
				const Vec3         dth = (dw - n.dot(dw) * n) * dt;
				// (re)starting: no rolling moment either (the one it had was booked as released when it separated)
				const Vec3         roll = rotateShear(handover ? Vec3(Vec3::Zero()) : s.roll, n);
				const CappedSpring rs   = cappedSpringStep(kr, L.rollingFriction * Reff * r.normalForce.norm(), roll, dth);
				s.roll                 = rs.value;
				torque[i] -= rs.value;
				torque[j] += rs.value;
				rollEnergy = rs.energy;
				if (L.trackEnergy) rolling += rs.dissipated;
			}
			if (L.trackEnergy) {
				elastic += r.elasticEnergy + rollEnergy;
				friction += r.frictionWork;
			}
		}
	}
	sums.elastic += elastic;
	sums.friction += friction;
	sums.rolling += rolling;
	sums.deepOnsets += deep;
	sums.touching += touching;
	sums.deepOnsetEnergy += deepEnergy;
	sums.maxOverlapRatio = maxRatio;
	if (maxI >= 0) {
		sums.maxOverlapI = maxI;
		sums.maxOverlapJ = maxJ;
	}
}

} // namespace flex
