// The Python module dqkit._dqkit (re-exported by the package dqkit): pybind11 bindings of the
// dqkit library with the C++ names. docs/python.md describes the API and its conventions.
#include "common.hpp"

namespace {
/// Precondition violations become Python exceptions (RuntimeError) instead of aborting the
/// interpreter; the bindings check their inputs first, so this is the last line of defence.
void throw_on_precondition(const dq::PreconditionViolation& v) {
  throw std::logic_error(std::string("dqkit precondition violated in ") + v.function + ": " + v.message);
}
}  // namespace

PYBIND11_MODULE(_dqkit, m) {
  m.doc() = "dqkit: dual quaternions, conversions, interpolation, skeletons, IK, skinning and motion files.";
  dq::set_precondition_handler(&throw_on_precondition);
  auto read_error = py::register_exception<dqpy::ReadError>(m, "ReadError", PyExc_ValueError);
  read_error.attr("__doc__") = "A file, text or model that could not be read or built; the message says what and where ('file:line: ...').";
  auto write_error = py::register_exception<dqpy::WriteError>(m, "WriteError", PyExc_OSError);
  write_error.attr("__doc__") = "A file that could not be written; the message names it and says why. The previous file, if any, is untouched.";
  dqpy::bind_values(m);
  dqpy::bind_batch(m);
  dqpy::bind_anim(m);
  dqpy::bind_io(m);
  dqpy::bind_ik(m);
  dqpy::bind_skin(m);
}
