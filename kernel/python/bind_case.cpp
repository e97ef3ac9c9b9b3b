#include "convert.h"

#include "st/io/case_file.h"

#include <pybind11/stl.h>

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

void bind_case(py::module_& m) {
  m.attr("CASE_FORMAT") = kCaseFormat;
  m.def(
      "read_case",
      [](const std::string& path) {
        const CaseFile c = read_case(path);
        py::dict d;
        d["path"] = c.path;
        d["name"] = c.name;
        d["bone"] = c.bone;
        d["boundary_points"] = from_points(c.boundary_points);
        d["inside"] = c.inside ? py::object(from_points({*c.inside}).attr("reshape")(3)) : py::object(py::none());
        d["thickness"] = c.thickness;
        d["clearance"] = c.clearance;
        d["resolution"] = c.resolution ? py::object(py::float_(*c.resolution)) : py::object(py::none());
        d["sampling_step"] = c.sampling_step ? py::object(py::int_(*c.sampling_step)) : py::object(py::none());
        py::list tubes;
        for (const TubeSpec& t : c.tubes) tubes.append(tube_dict(t));
        d["tubes"] = tubes;
        d["output"] = c.output ? py::object(py::str(*c.output)) : py::object(py::none());
        d["warnings"] = c.warnings;
        return d;
      },
      py::arg("path"), "Reads and checks a case file (surgical-template-case/1); raises ValueError naming the key.");
}
