// The Python module dqkit._dqkit (re-exported by the package dqkit): pybind11 bindings of the
// dqkit library with the C++ names. docs/python.md describes the API and its conventions.
#include "common.hpp"

namespace {
/// Precondition violations become Python exceptions (RuntimeError) instead of aborting the
/// interpreter; the bindings check their inputs first, so this is the last line of defence.
void throw_on_precondition(const dq::PreconditionViolation& v) {
  throw std::logic_error(std::string("dqkit precondition violated in ") + v.function + ": " + v.message);
}
/// Sets `type` with the message as text: messages name files, whose names may not be UTF-8 (a
/// byte 0xff would leave PyErr_SetString's message empty); such bytes appear as \xff.
void raise_with_message(const py::object& type, const char* message) {
  PyObject* text = PyUnicode_DecodeUTF8(message, static_cast<Py_ssize_t>(std::strlen(message)), "backslashreplace");
  if (!text) return;  // MemoryError is set
  PyErr_SetObject(type.ptr(), text);
  Py_DECREF(text);
}
}  // namespace

PYBIND11_MODULE(_dqkit, m) {
  m.doc() = "dqkit: dual quaternions, conversions, interpolation, skeletons, IK, skinning and motion files.";
  dq::set_precondition_handler(&throw_on_precondition);
  static py::exception<dqpy::ReadError> read_error(m, "ReadError", PyExc_ValueError);
  read_error.attr("__doc__") = "A file, text or model that could not be read or built; the message says what and where ('file:line: ...').";
  static py::exception<dqpy::WriteError> write_error(m, "WriteError", PyExc_OSError);
  write_error.attr("__doc__") = "A file that could not be written; the message names it and says why. The previous file, if any, is untouched.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const dqpy::ReadError& e) {
      raise_with_message(read_error, e.what());
    } catch (const dqpy::WriteError& e) {
      raise_with_message(write_error, e.what());
    }
  });
  dqpy::bind_values(m);
  dqpy::bind_batch(m);
  dqpy::bind_anim(m);
  dqpy::bind_io(m);
  dqpy::bind_ik(m);
  dqpy::bind_skin(m);
}
