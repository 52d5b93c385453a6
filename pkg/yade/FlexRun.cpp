// yade-flex adapter: FlexRun (GPL-2.0-or-later). What and why: FlexRun.hpp.
#include "FlexRun.hpp"
#include "FlexSceneCheck.hpp"

#include <boost/python/errors.hpp>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace yade {

YADE_PLUGIN((FlexRun));

namespace {
	constexpr long kSignalEvery = 1000; // steps between two looks at pending signals
}

long FlexRun::until(Real time, long maxSteps)
{
	if (std::isnan(time)) throw std::invalid_argument("FlexRun.until: time must not be NaN");
	if (maxSteps < 0) {
		std::ostringstream os;
		os << "FlexRun.until: maxSteps must be >= 0, got " << maxSteps;
		throw std::invalid_argument(os.str());
	}
	Omega& omega = Omega::instance();
	if (omega.isRunning()) throw std::runtime_error("FlexRun.until: the simulation is running (O.run); O.pause() it first");
	const shared_ptr<Scene> scene = omega.getScene(); // (held for the steps)
	if (!scene) throw std::runtime_error("FlexRun.until: no scene");
	long n = 0;
	if (maxSteps == 0 || !(scene->time < time)) return 0;
	// what the script may have changed since the last step: checked by the first step in full; the
	// others run no script in between (a PyRunner's run is seen by the check as in O.run)
	flexa::checkNextStepInFull(scene.get());
	flexa::ScriptFreeSteps scriptFree;
	while (n < maxSteps && scene->time < time) {
		scene->moveToNextTimeStep();
		++n;
		// a PyRunner may have started O.run() (its thread would step this scene too) or put
		// another scene in place
		if (omega.isRunning()) throw std::runtime_error("FlexRun.until: O.run() was called during the steps (from a PyRunner?); stopped");
		if (omega.getScene() != scene) break;
		// Ctrl-C and other signals: their Python handlers run here (a script: the next step is
		// checked in full)
		if (n % kSignalEvery == 0) {
			if (PyErr_CheckSignals() != 0) boost::python::throw_error_already_set();
			flexa::checkNextStepInFull(scene.get());
		}
	}
	return n;
}

} // namespace yade
