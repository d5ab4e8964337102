#include "vol/volume_reader.hpp"

#include "vol/hdf5_grid_io.hpp"
#include "vol/inr_reader.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace texsim::vol {

RgbGrid grey_from_scalar(const ScalarGrid& grid) {
  const auto [lo, hi] = std::minmax_element(grid.data().begin(), grid.data().end());
  const float low = *lo, range = *hi - *lo;
  RgbGrid grey(grid.dims());
  grey.set_spacing(grid.spacing());
  grey.set_origin(grid.origin());
  std::transform(grid.data().begin(), grid.data().end(), grey.data().begin(),
                 [&](float v) { return img::Rgb::grey(range > 0.0f ? (v - low) / range : 0.0f); });
  return grey;
}

RgbGrid read_volume(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  AnyGrid grid;
  if (ext == ".vdb") {
    grid = read_vdb(path);
  } else if (ext == ".vti") {
    grid = read_vti(path);
  } else if (ext == ".h5" || ext == ".hdf5") {
    grid = read_hdf5_grid(path);
  } else if (ext == ".inr") {
    grid = read_inr(path);
  } else {
    TEXSIM_INPUT_ERROR(path.string() << ": unsupported volume extension '" << ext
                                     << "', expected .vdb, .vti, .h5, .hdf5 or .inr");
  }
  if (auto* scalar = std::get_if<ScalarGrid>(&grid)) {
    return grey_from_scalar(*scalar);
  }
  return std::get<RgbGrid>(std::move(grid));
}

} // namespace texsim::vol
