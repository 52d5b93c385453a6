// yade-flex adapter: FlexRun, steps of the scene run from a script without Python between them
// (GPL-2.0-or-later).
//
// A script that records or tests something between steps calls O.step() in a loop. O.step() holds
// Python's lock while the step runs, so the scene check (FlexSceneCheck.hpp) must assume the
// script changed something before each step and checks every body. FlexRun.until() runs the steps
// up to a time in one call, holding Python's lock as O.step() does (a PyRunner runs as usual; other
// Python threads wait, as during O.step()): the first step checks the scene in full, the others as
// in O.run().
#pragma once
#include "FlexPch.hpp"

namespace yade {

class FlexRun : public Serializable {
public:
	/// Steps the current scene until O.time >= time or maxSteps steps were taken (or another scene
	/// was put in place); returns the number of steps taken. Refuses while O.run() runs, and stops
	/// with an error if a PyRunner starts it. Pending signals (Ctrl-C) are looked at every 1000
	/// steps. An engine's exception propagates as O.step()'s does (the step that threw does not
	/// count).
	static long until(Real time, long maxSteps);
	virtual ~FlexRun() = default;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexRun, Serializable,
		"Steps of the scene from a script without the interpreter between them (yadeflex.step_until).",
		/* no attributes */,
		/* ctor */,
		.def("until", &FlexRun::until, (boost::python::arg("time"), boost::python::arg("maxSteps")), "Step the current scene until O.time >= time [s] or maxSteps steps were taken; returns the number of steps taken. The first step checks the scene in full, the others as in O.run (no script runs between them; a PyRunner does). Raises what an engine raises, as O.step().").staticmethod("until")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexRun);

} // namespace yade
