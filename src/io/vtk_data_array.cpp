#include "io/vtk_data_array.hpp"

#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>

#include <algorithm>

namespace texsim::io {
namespace {

/// The VTK array class that stores T with T's own type: Float64, Int32, Int64 or Float32 in the
/// file.
template <class T> struct VtkArrayOf;
template <> struct VtkArrayOf<double> { using type = vtkDoubleArray; };
template <> struct VtkArrayOf<std::int32_t> { using type = vtkTypeInt32Array; };
template <> struct VtkArrayOf<std::int64_t> { using type = vtkTypeInt64Array; };
template <> struct VtkArrayOf<float> { using type = vtkFloatArray; };

template <class T>
vtkSmartPointer<vtkDataArray> typed_array(const std::string& name, int components,
                                          std::span<const T> values) {
  auto array = vtkSmartPointer<typename VtkArrayOf<T>::type>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / components));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

} // namespace

vtkSmartPointer<vtkDataArray> to_vtk_array(const DataField& field) {
  return std::visit(
      [&](const auto& values) { return typed_array(field.name, field.components, values); },
      field.values);
}

} // namespace texsim::io
