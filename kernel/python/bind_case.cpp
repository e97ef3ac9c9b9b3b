#include "convert.h"

#include "st/io/case_file.h"

#include <pybind11/stl.h>

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

void bind_case(py::module_& m) {
  m.attr("CASE_FORMAT") = kCaseFormat;
  m.def(
      "read_case", [](const std::string& path) { return case_dict(read_case(path)); }, py::arg("path"),
      "Reads and checks a case file (surgical-template-case/1); raises ValueError naming the key.");
  m.def(
      "write_case", [](const py::dict& c, const std::string& path) { write_case(to_case(c), path); }, py::arg("case"),
      py::arg("path"),
      "Writes a case file (read_case's keys; the bone relative to the file's folder), atomically, after checking "
      "it as read_case would; raises ValueError naming the key, writing nothing.");
}
