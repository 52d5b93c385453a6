// yade-flex adapter: flexa::Unstable raised in Python as yadeflex.Unstable (GPL-2.0-or-later).
#include "FlexUnstable.hpp"

#include <boost/python.hpp>

namespace {
void translate(const yade::flexa::Unstable& e)
{
	namespace py = boost::python;
	try {
		const py::object cls = py::import("yadeflex.errors").attr("Unstable");
		PyErr_SetString(cls.ptr(), e.what());
		return;
	} catch (const py::error_already_set&) {
		PyErr_Clear(); // (yadeflex not importable: a ValueError, as any refusal of a value)
	}
	PyErr_SetString(PyExc_ValueError, e.what());
}
// registered when YADE loads the plugin (from Python, during its import)
const bool registered = (boost::python::register_exception_translator<yade::flexa::Unstable>(&translate), true);
} // namespace
