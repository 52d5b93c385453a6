// Benchmark driver: a bed of grains stepped by the kernel's grain contacts on arrays of their own
// (pkg/kernel/GrainNeighbours, GrainContacts), without YADE (GPL-2.0-or-later). Run by
// bench/grain_kernel.py, which compares it with our plugin and LAMMPS on the same bed.
//
//     grain_kernel_bench GRAINS_FILE --steps N --warmup N --dt S --young PA --ks-over-kn X
//         --tan-phi X --rolling-stiffness X --rolling-friction X --density KG_M3 --gravity G
//         --cylinder R --skin M [--imp-radius R --imp-z Z --imp-speed V --imp-density KG_M3] [--threads N]
//
// GRAINS_FILE: one grain per line, "x y z r" [m]. The bed stands on a floor at z = 0 inside a
// vertical cylinder of radius R about the z axis. The grains' contacts are the kernel's law
// (yade-flex's sphere-sphere law: GrainContacts.hpp); the floor and the cylinder are plain linear
// springs (kn = E r, the floor with Coulomb friction and a shear spring per grain, the cylinder
// frictionless), the plugin's wall contacts being a few percent of the bed's. Leap-frog
// integration, gravity along -z, each grain's inertia 2/5 m r^2, no orientation. Prints one line
// "GK_RESULT <us per particle-step> <active contacts> <listed pairs> <list builds> <kinetic
// energy J> <fastest grain m/s> <energy terms J: elastic friction rolling> <impactor's peak
// contact force kN> <its depth m> <its final vertical speed m/s>" after the timed steps. With
// --imp-radius > 0 an impactor (a sphere of that radius and density on the axis, its centre at
// imp-z, moving down at imp-speed) is added after the grains: the impact of lammps_grains.py;
// its peak force is sampled every 10 timed steps, its depth from the start of the timing.
//
// --compare 1 (tests/yade/test_grain_kernel.py): each line "x y z r vx vy vz wx wy wz"; every grain
// moves at its constant velocity and turns at its constant angular velocity (as YADE's bodies
// with every DOF blocked: inverse mass 0), no floor, no cylinder, no gravity; --compare 2: the
// same grains free (leap-frog, mass and inertia from --density); --steps steps, no warm-up; prints "GK_FORCE i fx fy fz tx ty tz" of the last step for every
// grain, then "GK_ENERGY <elastic at the last step> <friction> <rolling> <deep onsets>".
#include "kernel/GrainContacts.hpp"
#include "kernel/GrainNeighbours.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

using namespace flex;

int main(int argc, char** argv)
{
	if (argc < 2) {
		std::cerr << "usage: grain_kernel_bench GRAINS_FILE [--steps N] [--warmup N] [--dt S] ...\n";
		return 2;
	}
	std::map<std::string, double> o { { "steps", 3000 }, { "warmup", 200 }, { "dt", 3.25e-5 }, { "young", 1e8 }, { "ks-over-kn", 0.3 },
		{ "tan-phi", std::tan(38 * M_PI / 180) }, { "rolling-stiffness", 1 }, { "rolling-friction", 0.1 }, { "density", 2650 }, { "gravity", 9.81 },
		{ "cylinder", 0.5 }, { "skin", 0.016 }, { "compare", 0 }, { "imp-radius", 0 }, { "imp-z", 0 }, { "imp-speed", 0 }, { "imp-density", 2400 },
		{ "threads", 1 } };
	for (int k = 2; k + 1 < argc; k += 2) {
		if (std::strncmp(argv[k], "--", 2) != 0 || !o.count(argv[k] + 2)) {
			std::cerr << "grain_kernel_bench: unknown option " << argv[k] << "\n";
			return 2;
		}
		o[argv[k] + 2] = std::atof(argv[k + 1]);
	}
	std::vector<Vec3>   pos, vel, angVel, force, torque, floorShear;
	std::vector<double> radius, invMass, invInertia;
	const bool          compare = o["compare"] != 0, free = o["compare"] == 2;
	{
		std::ifstream in(argv[1]);
		double        x, y, z, r, v[6];
		while (in >> x >> y >> z >> r) {
			if (compare)
				for (double& c : v)
					in >> c;
			if (!(r > 0)) {
				std::cerr << "grain_kernel_bench: a grain of radius " << r << "\n";
				return 2;
			}
			const double m = o["density"] * 4.0 / 3.0 * M_PI * r * r * r;
			pos.emplace_back(x, y, z);
			radius.push_back(r);
			invMass.push_back(compare && !free ? 0.0 : 1 / m);
			invInertia.push_back(1 / (0.4 * m * r * r));
			vel.push_back(compare ? Vec3(v[0], v[1], v[2]) : Vec3(Vec3::Zero()));
			angVel.push_back(compare ? Vec3(v[3], v[4], v[5]) : Vec3(Vec3::Zero()));
		}
	}
	if (o["imp-radius"] > 0 && !compare) {
		const double r = o["imp-radius"], m = o["imp-density"] * 4.0 / 3.0 * M_PI * r * r * r;
		pos.emplace_back(0, 0, o["imp-z"]);
		radius.push_back(r);
		invMass.push_back(1 / m);
		invInertia.push_back(1 / (0.4 * m * r * r));
		vel.emplace_back(0, 0, -o["imp-speed"]);
		angVel.push_back(Vec3::Zero());
	}
	const long n = (long)pos.size();
	if (n == 0) {
		std::cerr << "grain_kernel_bench: no grains in " << argv[1] << "\n";
		return 2;
	}
	force.assign(n, Vec3::Zero());
	torque.assign(n, Vec3::Zero());
	floorShear.assign(n, Vec3::Zero());
	GrainLaw law;
	law.young            = o["young"];
	law.ksOverKn         = o["ks-over-kn"];
	law.tanPhi           = o["tan-phi"];
	law.rollingStiffness = o["rolling-stiffness"];
	law.rollingFriction  = o["rolling-friction"];
	GrainContacts   contacts(law);
	GrainNeighbours list(o["skin"]);
	const double    dt = o["dt"], g = o["gravity"], R = o["cylinder"];
	double          elastic = 0, friction = 0, rolling = 0;
	long            lost = 0, deepOnsets = 0;
	// several threads (--threads): each runs one part of the spheres' pairs (GrainContacts::splitAt)
	// into force and torque sums of its own, added after the pass; walls and integration split by
	// sphere
	const int                      threads = std::max(1, (int)o["threads"]);
	std::vector<std::vector<Vec3>> partForce(threads), partTorque(threads);
	std::vector<GrainSums>         part(threads);
	for (int t = 1; t < threads; ++t) {
		partForce[t].assign(n, Vec3::Zero());
		partTorque[t].assign(n, Vec3::Zero());
	}
	const auto wallsAndMotion = [&](long i) {
		if (compare) { // constant velocities (every DOF blocked), or free without gravity
			if (free) {
				vel[i] += force[i] * invMass[i] * dt;
				angVel[i] += torque[i] * invInertia[i] * dt;
			}
			pos[i] += vel[i] * dt;
			return;
		}
		const double r = radius[i], kn = law.young * r, ks = law.ksOverKn * kn;
		const double dFloor = r - pos[i].z();
		if (dFloor > 0) { // the floor: normal +z, shear spring capped at tanPhi Fn
			const Vec3   c  = pos[i] - Vec3(0, 0, r - 0.5 * dFloor);
			const Vec3   vc = vel[i] + angVel[i].cross(c - pos[i]);
			const Vec3   vt(vc.x(), vc.y(), 0);
			Vec3         fs  = floorShear[i] - ks * vt * dt;
			const double cap = law.tanPhi * kn * dFloor;
			if (fs.squaredNorm() > cap * cap) fs *= cap / fs.norm();
			floorShear[i] = fs;
			const Vec3 F  = Vec3(0, 0, kn * dFloor) + fs;
			force[i] += F;
			torque[i] += (c - pos[i]).cross(F);
		} else
			floorShear[i].setZero();
		const double rho = std::hypot(pos[i].x(), pos[i].y()), dSide = rho + r - R;
		if (dSide > 0 && rho > 0) force[i] -= kn * dSide * Vec3(pos[i].x() / rho, pos[i].y() / rho, 0);
		vel[i] += (force[i] * invMass[i] - Vec3(0, 0, g)) * dt;
		angVel[i] += torque[i] * invInertia[i] * dt;
		pos[i] += vel[i] * dt;
	};
	auto step = [&](long iter) {
		if (list.stale(pos.data(), n)) {
			list.build(pos.data(), radius.data(), n);
			lost += contacts.follow(list);
		}
		const GrainMotion m { pos.data(), vel.data(), angVel.data(), radius.data(), invMass.data(), n };
#pragma omp parallel num_threads(threads)
		{
			int t = 0;
#ifdef _OPENMP
			t = omp_get_thread_num();
#endif
			Vec3* f = t == 0 ? force.data() : partForce[t].data();
			Vec3* q = t == 0 ? torque.data() : partTorque[t].data();
			for (long i = 0; i < n; ++i) {
				f[i].setZero();
				q[i].setZero();
			}
			part[t]        = GrainSums();
			part[t].force  = f;
			part[t].torque = q;
			contacts.step(m, iter, dt, part[t], contacts.splitAt(t, threads), contacts.splitAt(t + 1, threads));
#pragma omp barrier
#pragma omp for schedule(static)
			for (long i = 0; i < n; ++i) {
				for (int k = 1; k < threads; ++k) {
					force[i] += partForce[k][i];
					torque[i] += partTorque[k][i];
				}
				wallsAndMotion(i);
			}
		}
		elastic = 0;
		for (const GrainSums& s : part) {
			elastic += s.elastic;
			friction += s.friction;
			rolling += s.rolling;
			deepOnsets += s.deepOnsets;
		}
	};
	const long warmup = compare ? 0 : (long)o["warmup"], steps = (long)o["steps"];
	long       iter = 0;
	for (; iter < warmup; ++iter)
		step(iter);
	const bool   impactor = o["imp-radius"] > 0 && !compare;
	const double z0       = pos[n - 1].z();
	double       peak     = 0;
	const auto   t0       = std::chrono::steady_clock::now();
	for (; iter < warmup + steps; ++iter) {
		step(iter);
		if (impactor && (iter - warmup) % 10 == 0) peak = std::max(peak, std::abs(force[n - 1].z()));
	}
	const double t  = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	double       ke = 0, vmax = 0;
	for (long i = 0; i < n - (impactor ? 1 : 0); ++i) { // (the grains)
		ke += 0.5 * vel[i].squaredNorm() / invMass[i];
		vmax = std::max(vmax, vel[i].norm());
	}
	if (lost != 0) {
		std::cerr << "grain_kernel_bench: " << lost << " contacts lost at a list build\n";
		return 1;
	}
	if (compare) {
		for (long i = 0; i < n; ++i)
			std::printf("GK_FORCE %ld %.17g %.17g %.17g %.17g %.17g %.17g\n", i, force[i].x(), force[i].y(), force[i].z(), torque[i].x(),
			        torque[i].y(), torque[i].z());
		std::printf("GK_ENERGY %.17g %.17g %.17g %ld\n", elastic, friction, rolling, deepOnsets);
		return 0;
	}
	std::printf("GK_RESULT %.6f %ld %ld %ld %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g\n", 1e6 * t / ((double)steps * n), contacts.active(), list.pairs(),
	        list.builds(), ke, vmax, elastic, friction, rolling, impactor ? peak / 1e3 : 0.0, impactor ? z0 - pos[n - 1].z() : 0.0,
	        impactor ? vel[n - 1].z() : 0.0);
	return 0;
}
