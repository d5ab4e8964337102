#pragma once
/// Axis-aligned cross sections of a volume as PNG pictures, the way solid texture results are
/// shown (Su 2008 chapter 5): the planes x = const (YZ), y = const (XZ) and z = const (XY), and
/// the three side by side; an exemplar's above a result's.
///
/// Orientation: a plane's first remaining axis runs to the right and its second one upwards
/// (YZ: y right, z up; XZ: x right, z up; XY: x right, y up), so the pictures read like plots.
#include "img/image.hpp"
#include "vol/channel_grid.hpp"

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace texsim::vol {

/// The three cross sections x = positions[0] (YZ), y = positions[1] (XZ) and z = positions[2]
/// (XY) of a 1- (grey) or 3-channel (RGB) volume, oriented as above, filled from its z-planes as
/// they come: a volume split into z-slabs over ranks is never whole on one rank.
class CrossSections {
public:
  /// Throws InputError naming the axis if a position is outside `dims`, Error if `channels` is
  /// neither 1 nor 3.
  CrossSections(Dims dims, int channels, const std::array<int, 3>& positions);

  /// Planes z_first, z_first + 1, ... of the volume: whole planes, x fastest, `channels` values
  /// per voxel.
  void add_planes(int z_first, std::span<const float> values);

  const std::array<int, 3>& positions() const { return positions_; }
  /// The picture of plane `axis`; complete once every z-plane has been added. Pixels of planes not
  /// added are 0, so the sections of disjoint plane ranges add up to the whole volume's.
  const img::RgbImage& picture(int axis) const { return pictures_[axis]; }
  img::RgbImage& picture(int axis) { return pictures_[axis]; }

private:
  Dims dims_;
  int channels_;
  std::array<int, 3> positions_;
  std::array<img::RgbImage, 3> pictures_;
};

/// The plane `axis` (0: x, 1: y, 2: z) = `position` of a 1-channel (grey) or 3-channel (RGB)
/// grid, oriented as above. Throws InputError if `position` is outside the grid.
img::RgbImage cross_section(const ChannelGrid& colours, int axis, int position);

/// Writes `<basename>_x<p0>.png` (the YZ plane x = positions[0]), `<basename>_y<p1>.png` (XZ),
/// `<basename>_z<p2>.png` (XY) and `<basename>_slices.png` (the three in that order, left to
/// right, bottom-aligned on a white background with a 4-pixel gap) into `directory`, created if
/// missing, and returns their paths in that order. Colours are clamped to [0, 1] and written with
/// 8 bits; each file is written atomically (img::write_png). Throws InputError naming the axis if
/// a position is outside the grid, Error naming the file if a file cannot be written. Not
/// collective: call on one rank.
std::vector<std::filesystem::path> write_cross_sections(const std::filesystem::path& directory,
                                                        const std::string& basename,
                                                        const ChannelGrid& colours,
                                                        const std::array<int, 3>& positions);
/// The same from sections already taken.
std::vector<std::filesystem::path> write_cross_sections(const std::filesystem::path& directory,
                                                        const std::string& basename,
                                                        const CrossSections& sections);
/// The paths write_cross_sections writes, in its order.
std::vector<std::filesystem::path> cross_section_paths(const std::filesystem::path& directory,
                                                       const std::string& basename,
                                                       const std::array<int, 3>& positions);

/// One picture comparing an exemplar with a synthesized result at the same voxel scale: the
/// exemplar's three cross sections through its centre (x, y, z planes, left to right) above the
/// result's three at `result_positions`, rows as in `<basename>_slices.png`, 4 pixels apart on
/// white. Written atomically (img::write_png), its directory created if missing; returns `path`.
/// Throws InputError naming the axis if a position is outside the result. Not collective.
std::filesystem::path write_comparison(const std::filesystem::path& path,
                                       const ChannelGrid& exemplar, const ChannelGrid& result,
                                       const std::array<int, 3>& result_positions);
/// The same with the result's sections already taken.
std::filesystem::path write_comparison(const std::filesystem::path& path,
                                       const ChannelGrid& exemplar, const CrossSections& result);

} // namespace texsim::vol
