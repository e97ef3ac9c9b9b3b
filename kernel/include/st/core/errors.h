#pragma once
// Error types of the kernel.
//
// InvalidInput: the caller passed something that breaks a documented precondition (a corrupt file,
// NaN coordinates, too few control points, a negative thickness). Derived from std::invalid_argument,
// so pybind11 turns it into ValueError. The message names what and where.
//
// GeometryError: the input is well formed but its geometry cannot give a result (a boundary loop that
// does not enclose a region, a curve that runs into a hole). Derived from std::runtime_error, so
// pybind11 turns it into RuntimeError. The message says what failed and where (coordinates in mm).

#include <stdexcept>
#include <string>

namespace st {

class InvalidInput : public std::invalid_argument {
public:
  using std::invalid_argument::invalid_argument;
};

class GeometryError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A closed curve on a surface that crosses itself (see trace_surface_curve): a GeometryError the
/// caller can act on, e.g. by sampling the curve more coarsely.
class CurveCrossesItself : public GeometryError {
public:
  using GeometryError::GeometryError;
};

} // namespace st
