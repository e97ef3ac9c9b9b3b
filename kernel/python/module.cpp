// stkernel: the surgical-template mesh kernel for Python. numpy arrays in and out by value; the GIL
// is released during heavy work; invalid input raises ValueError, geometric failure RuntimeError.

#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_mesh(py::module_& m);
void bind_template(py::module_& m);
void bind_case(py::module_& m);
void bind_boolean(py::module_& m);
void bind_plan(py::module_& m);
#ifdef ST_HAVE_OCCT
void bind_occt(py::module_& m);
#endif

PYBIND11_MODULE(stkernel, m) {
  m.doc() = "Surgical template mesh kernel: boundary curves, cuts, offsets, ruled walls, solid checks";
  bind_mesh(m);
  bind_template(m);
  bind_case(m);
  bind_boolean(m);
  bind_plan(m);
  // The OpenCASCADE sleeves are an optional part of the build (ST_WITH_OCCT); callers test has_occt.
#ifdef ST_HAVE_OCCT
  m.attr("has_occt") = true;
  bind_occt(m);
#else
  m.attr("has_occt") = false;
#endif
}
