#pragma once
/// A DataField as a VTK array of the field's own type (Float64, Int32 or Int64), for the VTK
/// writers of io.
#include "io/surface_piece.hpp"

#include <vtkDataArray.h>
#include <vtkSmartPointer.h>

namespace texsim::io {

/// A copy of `field`'s values in a named VTK array with its components.
vtkSmartPointer<vtkDataArray> to_vtk_array(const DataField& field);

} // namespace texsim::io
