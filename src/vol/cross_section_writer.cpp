#include "vol/cross_section_writer.hpp"

#include "core/error.hpp"
#include "img/image_io.hpp"

#include <algorithm>
#include <system_error>

namespace texsim::vol {
namespace {

constexpr char kAxisNames[3] = {'x', 'y', 'z'};

/// Side by side, bottom-aligned, on white, `gap` pixels apart.
img::RgbImage side_by_side(const std::vector<img::RgbImage>& pictures, int gap) {
  int width = gap * (static_cast<int>(pictures.size()) - 1), height = 0;
  for (const img::RgbImage& picture : pictures) {
    width += picture.width();
    height = std::max(height, picture.height());
  }
  img::RgbImage combined(width, height, img::Rgb::grey(1.0f));
  int left = 0;
  for (const img::RgbImage& picture : pictures) {
    const int top = height - picture.height();
    for (int y = 0; y < picture.height(); ++y) {
      for (int x = 0; x < picture.width(); ++x) {
        combined.at(left + x, top + y) = picture.at(x, y);
      }
    }
    left += picture.width() + gap;
  }
  return combined;
}

/// Rows top to bottom, left-aligned, on white, `gap` pixels apart.
img::RgbImage stacked(const std::vector<img::RgbImage>& rows, int gap) {
  int width = 0, height = gap * (static_cast<int>(rows.size()) - 1);
  for (const img::RgbImage& row : rows) {
    width = std::max(width, row.width());
    height += row.height();
  }
  img::RgbImage combined(width, height, img::Rgb::grey(1.0f));
  int top = 0;
  for (const img::RgbImage& row : rows) {
    for (int y = 0; y < row.height(); ++y)
      for (int x = 0; x < row.width(); ++x)
        combined.at(x, top + y) = row.at(x, y);
    top += row.height() + gap;
  }
  return combined;
}

/// The three cross sections at `positions`, side by side.
img::RgbImage three_sections(const ChannelGrid& colours, const std::array<int, 3>& positions) {
  std::vector<img::RgbImage> pictures;
  for (int axis = 0; axis < 3; ++axis)
    pictures.push_back(cross_section(colours, axis, positions[axis]));
  return side_by_side(pictures, 4);
}

void make_directory(const std::filesystem::path& directory) {
  std::error_code failure;
  std::filesystem::create_directories(directory, failure);
  TEXSIM_VERIFY(!failure,
                "cannot create the directory " << directory.string() << ": " << failure.message());
}

} // namespace

img::RgbImage cross_section(const ChannelGrid& colours, int axis, int position) {
  TEXSIM_VERIFY(axis >= 0 && axis < 3, "cross_section: axis must be 0, 1 or 2, got " << axis);
  TEXSIM_VERIFY(colours.channels() == 1 || colours.channels() == 3,
                "cross sections need 1 (grey) or 3 (RGB) channels, got " << colours.channels());
  const Dims dims = colours.dims();
  const int n[3] = {dims.nx, dims.ny, dims.nz};
  if (position < 0 || position >= n[axis]) {
    TEXSIM_INPUT_ERROR("cross section " << kAxisNames[axis] << " = " << position
                                        << " is outside the volume (0 to " << n[axis] - 1 << ")");
  }
  // The remaining axes in increasing order: the first runs right, the second up.
  const int right = axis == 0 ? 1 : 0;
  const int up = axis == 2 ? 1 : 2;
  img::RgbImage picture(n[right], n[up]);
  int voxel[3];
  voxel[axis] = position;
  for (int v = 0; v < n[up]; ++v) {
    for (int u = 0; u < n[right]; ++u) {
      voxel[right] = u;
      voxel[up] = v;
      const auto c = colours.voxel(colours.index(voxel[0], voxel[1], voxel[2]));
      picture.at(u, n[up] - 1 - v) =
          colours.channels() == 3 ? img::Rgb{c[0], c[1], c[2]} : img::Rgb::grey(c[0]);
    }
  }
  return picture;
}

std::vector<std::filesystem::path> write_cross_sections(const std::filesystem::path& directory,
                                                        const std::string& basename,
                                                        const ChannelGrid& colours,
                                                        const std::array<int, 3>& positions) {
  std::vector<img::RgbImage> pictures;
  for (int axis = 0; axis < 3; ++axis) {
    pictures.push_back(cross_section(colours, axis, positions[axis]));
  }
  make_directory(directory);
  std::vector<std::filesystem::path> paths;
  for (int axis = 0; axis < 3; ++axis) {
    paths.push_back(directory /
                    (basename + "_" + kAxisNames[axis] + std::to_string(positions[axis]) + ".png"));
    img::write_png(paths.back(), pictures[axis]);
  }
  paths.push_back(directory / (basename + "_slices.png"));
  img::write_png(paths.back(), side_by_side(pictures, 4));
  return paths;
}

std::filesystem::path write_comparison(const std::filesystem::path& path,
                                       const ChannelGrid& exemplar, const ChannelGrid& result,
                                       const std::array<int, 3>& result_positions) {
  const Dims e = exemplar.dims();
  const img::RgbImage picture = stacked({three_sections(exemplar, {e.nx / 2, e.ny / 2, e.nz / 2}),
                                         three_sections(result, result_positions)},
                                        4);
  make_directory(path.parent_path());
  img::write_png(path, picture);
  return path;
}

} // namespace texsim::vol
