// yade-flex adapter: the one exception of a run that became unstable (GPL-2.0-or-later).
//
// Thrown by the scene check (a body's motion not finite), the integrator (a motion it made not
// finite), FlexGuard and FlexTimeStepper (a collapsed critical step, minDtFraction). Python sees
// it as yadeflex.Unstable, a subclass of both ValueError (what the scene check raises for a bad
// value) and RuntimeError (what FlexGuard raised): the translator registered in FlexUnstable.cpp;
// where yadeflex cannot be imported, as ValueError.
#pragma once
#include <stdexcept>

namespace yade {
namespace flexa {
	struct Unstable : std::invalid_argument {
		using std::invalid_argument::invalid_argument;
	};
} // namespace flexa
} // namespace yade
