#pragma once
// Kernel mesh <-> VTK polydata, shared by the benchmark's reference programs.

#include "st/core/mesh.h"

#include <vtkCellArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <vector>

namespace st::bench {

inline vtkSmartPointer<vtkPolyData> to_vtk(const TriangleMesh& mesh) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(mesh.vertex_count());
  for (Index v = 0; v < mesh.vertex_count(); ++v) points->SetPoint(v, mesh.positions[v].data());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(mesh.face_count() + 1);
  connectivity->SetNumberOfValues(3 * static_cast<vtkIdType>(mesh.face_count()));
  for (Index f = 0; f < mesh.face_count(); ++f) {
    offsets->SetValue(f, 3 * static_cast<vtkIdType>(f));
    for (int k = 0; k < 3; ++k) connectivity->SetValue(3 * static_cast<vtkIdType>(f) + k, mesh.triangles[f][k]);
  }
  offsets->SetValue(mesh.face_count(), 3 * static_cast<vtkIdType>(mesh.face_count()));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  return poly;
}

/// The polygons of `poly` (fan-triangulated), with only the points they use and VTK's point
/// sharing as it is (no welding).
inline TriangleMesh from_vtk(vtkPolyData* poly) {
  TriangleMesh all;
  all.positions.resize(static_cast<std::size_t>(poly->GetNumberOfPoints()));
  for (vtkIdType v = 0; v < poly->GetNumberOfPoints(); ++v) poly->GetPoint(v, all.positions[v].data());
  vtkCellArray* polys = poly->GetPolys();
  const vtkIdType* ids = nullptr;
  vtkIdType n = 0;
  std::vector<Index> faces;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
    for (vtkIdType k = 1; k + 1 < n; ++k) {
      faces.push_back(all.face_count());
      all.triangles.push_back({static_cast<Index>(ids[0]), static_cast<Index>(ids[k]), static_cast<Index>(ids[k + 1])});
    }
  return st::submesh(all, faces);
}

} // namespace st::bench
