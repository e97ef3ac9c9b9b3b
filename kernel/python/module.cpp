// stkernel: the surgical-template mesh kernel for Python. numpy arrays in and out by value; the GIL
// is released during heavy work; invalid input raises ValueError, geometric failure RuntimeError.

#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_mesh(py::module_& m);
void bind_template(py::module_& m);
void bind_case(py::module_& m);

PYBIND11_MODULE(stkernel, m) {
  m.doc() = "Surgical template mesh kernel: boundary curves, cuts, offsets, ruled walls, solid checks";
  bind_mesh(m);
  bind_template(m);
  bind_case(m);
}
