#include "Errors.hpp"

#include <regex>

#include "core/Interrupt.hpp"
#include "core/Types.hpp"

namespace flexsens_python {

namespace {

// The classes, created once at import (module lifetime: never freed).
PyObject* gError = nullptr;
PyObject* gInputError = nullptr;
PyObject* gNumericalError = nullptr;
PyObject* gOutputError = nullptr;
PyObject* gDirectoryBusy = nullptr;

PyObject* newClass(py::module_& m, const char* name, PyObject* base, const char* doc) {
  const std::string qualified = std::string("flexsens.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
  if (!cls) throw py::error_already_set();
  m.add_object(name, py::handle(cls));
  return cls;
}

/// Raises `cls(message)` with the given attributes.
void raiseWith(PyObject* cls, const std::string& message, const py::dict& attributes) {
  py::object error = py::reinterpret_borrow<py::object>(cls)(message);
  for (const auto& [key, value] : attributes) error.attr(key) = value;
  PyErr_SetObject(cls, error.ptr());
}

/// file, line, key and message of an input error's text. The readers write
/// "FILE:LINE:COLUMN: key 'KEY': MESSAGE" (or without the line), options "option --NAME: MESSAGE"
/// (the key is the Python keyword: --t-end -> t_end); anything else is all message.
py::dict inputErrorFields(const std::string& text) {
  static const std::regex located(R"(^(.*?)(?::(\d+):\d+)?: key '([^']*)': ([\s\S]*)$)");
  static const std::regex option(R"(^option (?:--)?([A-Za-z0-9_-]+)[^:]*: ([\s\S]*)$)");
  py::dict d;
  d["file"] = py::none();
  d["line"] = py::none();
  d["key"] = py::none();
  d["message"] = text;
  std::smatch mt;
  if (std::regex_match(text, mt, option)) {  // first: "option --t-end: key 'integrator.dt': ..." is an option's
    std::string key = mt[1].str();
    for (char& ch : key)
      if (ch == '-') ch = '_';
    d["key"] = key;
    d["message"] = mt[2].str();
  } else if (std::regex_match(text, mt, located)) {
    if (mt[1].length()) d["file"] = mt[1].str();
    if (mt[2].matched) d["line"] = std::stoi(mt[2].str());
    d["key"] = mt[3].str();
    d["message"] = mt[4].str();
  }
  return d;
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const flexsens::InputError& e) {
    raiseWith(gInputError, e.what(), inputErrorFields(e.what()));
  } catch (const flexsens::NumericalError& e) {
    py::dict attributes;
    attributes["result"] = py::none();
    raiseWith(gNumericalError, e.what(), attributes);
  } catch (const flexsens::DirectoryBusy& e) {
    PyErr_SetString(gDirectoryBusy, e.what());
  } catch (const flexsens::OutputError& e) {
    PyErr_SetString(gOutputError, e.what());
  } catch (const flexsens::Interrupted& e) {
    PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
  } catch (const flexsens::InterruptedBeforeRun& e) {
    PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
  }
}

}  // namespace

void registerErrors(py::module_& m) {
  gError = newClass(m, "Error", PyExc_RuntimeError, "Base class of flexsens' errors.");
  gInputError = newClass(m, "InputError", gError,
                         "A bad scene or argument. Attributes: file, line (None when not known), key (the "
                         "scene key or the keyword argument), message (the text after them).");
  gNumericalError = newClass(m, "NumericalError", gError,
                             "A numerical failure (Newton, a singular matrix, a non-finite value): the message "
                             "names the time and the quantity. Attribute result: the frames up to the failure "
                             "(status 'failed'), or None.");
  gOutputError = newClass(m, "OutputError", gError,
                          "Results could not be written, or the output folder holds files flexsens did not "
                          "write (nothing touched).");
  gDirectoryBusy = newClass(m, "DirectoryBusy", gOutputError, "Another run writes the same output folder.");
  py::register_exception_translator(translate);
}

void raiseNumericalError(const std::string& message, py::object result) {
  py::dict attributes;
  attributes["result"] = result;
  raiseWith(gNumericalError, message, attributes);
  throw py::error_already_set();
}

}  // namespace flexsens_python
