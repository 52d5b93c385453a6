// yade-flex adapter: the one message for an engine's or functor's attribute out of its range
// (GPL-2.0-or-later).
#pragma once
#include "FlexPch.hpp"

#include <sstream>
#include <stdexcept>
#include <string>

namespace yade {
namespace flexa {
	/// Throws std::invalid_argument "Class.field must be <need>, got <v>", followed by
	/// " (the one labelled 'label')" when the object has a label: the wording every set-time and
	/// step-time check of an engine or functor attribute uses (FlexGuard, FlexTimeStepper, the
	/// scene check's engine pass), so that one pattern finds them all.
	template <class T> [[noreturn]] void refuseAttribute(const std::string& className, const std::string& label, const char* field, const T& v, const char* need)
	{
		std::ostringstream os;
		os.precision(6);
		os << className << "." << field << " must be " << need << ", got " << v;
		if (!label.empty()) os << " (the one labelled '" << label << "')";
		throw std::invalid_argument(os.str());
	}
	/// The same for an object with getClassName() and a label (an Engine, a Functor).
	template <class E, class T> [[noreturn]] void refuseAttribute(const E& e, const char* field, const T& v, const char* need)
	{
		refuseAttribute(e.getClassName(), e.label, field, v, need);
	}
} // namespace flexa
} // namespace yade
