#pragma once
// Test helper: the type of a named array in a ParaView file (.vtu, .vtp, .pvtu, .pvtp, .vti), read
// back through VTK's own XML readers as ParaView reads it. Test programs using it link VTK.
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLGenericDataObjectReader.h>

#include <filesystem>
#include <string>

namespace texsim::test {

enum class ArrayAssociation { point, cell };

/// VTK_DOUBLE, VTK_TYPE_INT32, VTK_TYPE_INT64, ... of the array `name` of `file`; -1 if the file
/// cannot be read or has no such array.
inline int vtk_array_type(const std::filesystem::path& file, ArrayAssociation where,
                          const std::string& name) {
  vtkNew<vtkXMLGenericDataObjectReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  auto* data = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (data == nullptr)
    return -1;
  vtkDataArray* array = where == ArrayAssociation::point
                            ? data->GetPointData()->GetArray(name.c_str())
                            : data->GetCellData()->GetArray(name.c_str());
  return array != nullptr ? array->GetDataType() : -1;
}

} // namespace texsim::test
