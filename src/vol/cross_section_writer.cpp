#include "vol/cross_section_writer.hpp"

#include "core/error.hpp"
#include "img/image_io.hpp"

#include <algorithm>
#include <cstdint>
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

/// The three pictures of `sections`, side by side.
img::RgbImage side_by_side(const CrossSections& sections) {
  return side_by_side({sections.picture(0), sections.picture(1), sections.picture(2)}, 4);
}

/// The sections of a whole grid.
CrossSections sections_of(const ChannelGrid& colours, const std::array<int, 3>& positions) {
  CrossSections sections(colours.dims(), colours.channels(), positions);
  sections.add_planes(0, colours.data());
  return sections;
}

void make_directory(const std::filesystem::path& directory) {
  std::error_code failure;
  std::filesystem::create_directories(directory, failure);
  TEXSIM_VERIFY(!failure,
                "cannot create the directory " << directory.string() << ": " << failure.message());
}

} // namespace

CrossSections::CrossSections(Dims dims, int channels, const std::array<int, 3>& positions)
    : dims_(dims), channels_(channels), positions_(positions) {
  TEXSIM_VERIFY(channels == 1 || channels == 3,
                "cross sections need 1 (grey) or 3 (RGB) channels, got " << channels);
  const int n[3] = {dims.nx, dims.ny, dims.nz};
  for (int axis = 0; axis < 3; ++axis)
    if (positions[axis] < 0 || positions[axis] >= n[axis]) {
      TEXSIM_INPUT_ERROR("cross section " << kAxisNames[axis] << " = " << positions[axis]
                                          << " is outside the volume (0 to " << n[axis] - 1 << ")");
    }
  // The remaining axes in increasing order: the first runs right, the second up.
  pictures_ = {img::RgbImage(dims.ny, dims.nz), img::RgbImage(dims.nx, dims.nz),
               img::RgbImage(dims.nx, dims.ny)};
}

void CrossSections::add_planes(int z_first, std::span<const float> values) {
  const auto plane = static_cast<std::size_t>(dims_.nx) * static_cast<std::size_t>(dims_.ny) *
                     static_cast<std::size_t>(channels_);
  TEXSIM_VERIFY(values.size() % plane == 0 && z_first >= 0 &&
                    z_first + static_cast<std::int64_t>(values.size() / plane) <= dims_.nz,
                "cross sections: " << values.size() << " values from plane " << z_first
                                   << " are not whole planes of the " << dims_.nx << " x "
                                   << dims_.ny << " x " << dims_.nz << " volume");
  const auto colour = [&](std::size_t voxel) {
    const float* c = values.data() + voxel * static_cast<std::size_t>(channels_);
    return channels_ == 3 ? img::Rgb{c[0], c[1], c[2]} : img::Rgb::grey(c[0]);
  };
  const auto at = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims_.nx) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(dims_.ny) * static_cast<std::size_t>(k));
  };
  const int planes = static_cast<int>(values.size() / plane);
  for (int k = 0; k < planes; ++k) {
    const int z = z_first + k;
    for (int j = 0; j < dims_.ny; ++j)
      pictures_[0].at(j, dims_.nz - 1 - z) = colour(at(positions_[0], j, k));
    for (int i = 0; i < dims_.nx; ++i)
      pictures_[1].at(i, dims_.nz - 1 - z) = colour(at(i, positions_[1], k));
    if (z == positions_[2])
      for (int j = 0; j < dims_.ny; ++j)
        for (int i = 0; i < dims_.nx; ++i)
          pictures_[2].at(i, dims_.ny - 1 - j) = colour(at(i, j, k));
  }
}

img::RgbImage cross_section(const ChannelGrid& colours, int axis, int position) {
  TEXSIM_VERIFY(axis >= 0 && axis < 3, "cross_section: axis must be 0, 1 or 2, got " << axis);
  std::array<int, 3> positions{0, 0, 0};
  positions[axis] = position;
  return sections_of(colours, positions).picture(axis);
}

std::vector<std::filesystem::path> write_cross_sections(const std::filesystem::path& directory,
                                                        const std::string& basename,
                                                        const ChannelGrid& colours,
                                                        const std::array<int, 3>& positions) {
  return write_cross_sections(directory, basename, sections_of(colours, positions));
}

std::vector<std::filesystem::path> cross_section_paths(const std::filesystem::path& directory,
                                                       const std::string& basename,
                                                       const std::array<int, 3>& positions) {
  std::vector<std::filesystem::path> paths;
  for (int axis = 0; axis < 3; ++axis)
    paths.push_back(directory /
                    (basename + "_" + kAxisNames[axis] + std::to_string(positions[axis]) + ".png"));
  paths.push_back(directory / (basename + "_slices.png"));
  return paths;
}

std::vector<std::filesystem::path> write_cross_sections(const std::filesystem::path& directory,
                                                        const std::string& basename,
                                                        const CrossSections& sections) {
  make_directory(directory);
  const std::vector<std::filesystem::path> paths =
      cross_section_paths(directory, basename, sections.positions());
  for (int axis = 0; axis < 3; ++axis)
    img::write_png(paths[static_cast<std::size_t>(axis)], sections.picture(axis));
  img::write_png(paths.back(), side_by_side(sections));
  return paths;
}

std::filesystem::path write_comparison(const std::filesystem::path& path,
                                       const ChannelGrid& exemplar, const ChannelGrid& result,
                                       const std::array<int, 3>& result_positions) {
  return write_comparison(path, exemplar, sections_of(result, result_positions));
}

std::filesystem::path write_comparison(const std::filesystem::path& path,
                                       const ChannelGrid& exemplar, const CrossSections& result) {
  const Dims e = exemplar.dims();
  const img::RgbImage picture = stacked(
      {side_by_side(sections_of(exemplar, {e.nx / 2, e.ny / 2, e.nz / 2})), side_by_side(result)},
      4);
  make_directory(path.parent_path());
  img::write_png(path, picture);
  return path;
}

} // namespace texsim::vol
