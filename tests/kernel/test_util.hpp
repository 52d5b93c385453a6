// yade-flex kernel tests: shared tolerance and helpers (GPL-2.0-or-later)
#pragma once
#include "kernel/Types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

namespace flex::test {

inline double                   magnitude(double x) { return std::abs(x); }
template <class Derived> double magnitude(const Eigen::MatrixBase<Derived>& x) { return x.norm(); }
inline bool                     allFinite(double x) { return std::isfinite(x); }
template <class Derived> bool   allFinite(const Eigen::MatrixBase<Derived>& x) { return x.allFinite(); }

/// The one tolerance rule of the suite: |actual - expected| <= absTol + relTol * max(|actual|, |expected|)
/// (|.| the Euclidean norm for vectors and matrices). Use as EXPECT_TRUE(close(a, b, rel, abs)).
template <class A, class B>::testing::AssertionResult close(const A& actual, const B& expected, double relTol, double absTol = 0.0)
{
	const double err   = magnitude(actual - expected);
	const double scale = std::max(magnitude(actual), magnitude(expected));
	if (allFinite(actual) && allFinite(expected) && err <= absTol + relTol * scale) return ::testing::AssertionSuccess();
	std::ostringstream os;
	os.precision(17);
	os << "\n  actual   = " << actual << "\n  expected = " << expected << "\n  |error| = " << err << " > " << absTol << " + " << relTol << " * " << scale;
	return ::testing::AssertionFailure() << os.str();
}

/// Fixed-seed generator, so every run checks the same "random" states.
struct Rng {
	std::mt19937_64 gen;
	explicit Rng(unsigned seed = 12345)
	        : gen(seed)
	{
	}
	double uniform(double lo = -1.0, double hi = 1.0) { return std::uniform_real_distribution<double>(lo, hi)(gen); }
	Vec3   vec(double scale = 1.0) { return scale * Vec3(uniform(), uniform(), uniform()); }
	Vec3   unit()
	{
		for (;;) {
			const Vec3 v = vec();
			if (v.norm() > 0.1 && v.norm() <= 1.0) return v.normalized();
		}
	}
	Quat quat() { return Quat(Eigen::AngleAxisd(uniform(-M_PI, M_PI), unit())); }
};

/// Rotation by the rotation vector th (|th| = angle, direction = axis).
inline Quat rotvec(const Vec3& th)
{
	const double a = th.norm();
	if (a == 0) return Quat::Identity();
	return Quat(Eigen::AngleAxisd(a, th / a));
}

} // namespace flex::test
