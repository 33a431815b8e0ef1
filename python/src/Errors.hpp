// flexsens' exceptions in Python: flexsens.Error and below it InputError (with the file, line
// and key a scene error names), NumericalError (with the partial result when a run got that
// far), OutputError and DirectoryBusy; Interrupted becomes KeyboardInterrupt. The C++ types
// (core/Types.hpp, core/Interrupt.hpp) are translated wherever they escape a binding.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

namespace flexsens_python {

namespace py = pybind11;

/// Creates the exception classes in module m and registers the translation.
void registerErrors(py::module_& m);

/// Raises flexsens.NumericalError(message) with its `result` attribute set (None: no frames).
[[noreturn]] void raiseNumericalError(const std::string& message, py::object result);

}  // namespace flexsens_python
