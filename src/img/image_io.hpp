#pragma once
/// PNG and JPEG images through VTK's readers and writer.
#include "img/image.hpp"

#include <cstdint>
#include <filesystem>
#include <span>

namespace texsim::img {

/// Reads a .png or .jpg/.jpeg file (chosen by extension, case-insensitive). Grey images are
/// replicated into three channels, an alpha channel is dropped, 8-bit values map to v / 255 and
/// 16-bit PNG values to v / 65535. Row 0 of the result is the top row of the picture.
/// Throws InputError naming the file if it is missing, not a readable PNG/JPEG, or of another type.
RgbImage read_image(const std::filesystem::path& path);

/// Writes an 8-bit RGB PNG atomically (temporary name, fsync, rename: core/atomic_output.hpp);
/// channels are clamped to [0, 1] and rounded to the nearest of v / 255. Throws Error naming the
/// file if it cannot be written, leaving a file already at `path` as it was.
void write_png(const std::filesystem::path& path, const RgbImage& image);

/// Writes `values` (row-major, row 0 at the top) as a 16-bit grey PNG, atomically: a height or
/// displacement image for renderers, 65535 levels instead of 255. Throws texsim::Error naming the
/// file if it cannot be written.
void write_png16(const std::filesystem::path& path, std::span<const std::uint16_t> values,
                 int width, int height);

/// The value read back after write_png: each channel clamped and rounded to a multiple of 1/255.
RgbImage quantize_8bit(const RgbImage& image);

/// One channel as write_png stores it: clamped to [0, 1], rounded to the nearest of v / 255.
std::uint8_t channel_to_byte(float value);

} // namespace texsim::img
