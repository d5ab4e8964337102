#include "io/parallel_png_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "par/collective.hpp"
#include "par/gather_to_root.hpp"

#include <mpi.h>
#include <zlib.h>

#include <array>
#include <cstdlib>
#include <string>
#include <vector>

namespace texsim::io {
namespace {

/// zlib level 3, as img::write_png: most of level 6's size at about twice its speed.
constexpr int kDeflateLevel = 3;

int bytes_per_pixel(PngPixels pixels) {
  return pixels == PngPixels::rgb8 ? 3 : 2;
}

int paeth(int left, int up, int up_left) {
  const int p = left + up - up_left;
  const int to_left = std::abs(p - left), to_up = std::abs(p - up),
            to_up_left = std::abs(p - up_left);
  if (to_left <= to_up && to_left <= to_up_left)
    return left;
  return to_up <= to_up_left ? up : up_left;
}

/// The five PNG filters' outputs for byte i of a row (x) from its left (a), upper (b) and
/// upper-left (c) neighbours: none, sub, up, average, Paeth.
std::array<std::uint8_t, 5> filtered(int x, int a, int b, int c) {
  return {std::uint8_t(x), std::uint8_t(x - a), std::uint8_t(x - b), std::uint8_t(x - (a + b) / 2),
          std::uint8_t(x - paeth(a, b, c))};
}

/// Row `row` filtered into out[0] (the filter type) and out[1..]: the filter with the least sum
/// of absolute values as signed bytes (the PNG specification's heuristic).
void filter_row(const std::uint8_t* row, const std::uint8_t* above, std::size_t row_bytes, int bpp,
                std::uint8_t* out) {
  const auto neighbours = [&](std::size_t i) {
    const int a = i >= std::size_t(bpp) ? row[i - std::size_t(bpp)] : 0;
    const int c = i >= std::size_t(bpp) ? above[i - std::size_t(bpp)] : 0;
    return std::array<int, 3>{a, above[i], c};
  };
  std::array<long, 5> cost{};
  for (std::size_t i = 0; i < row_bytes; ++i) {
    const auto [a, b, c] = neighbours(i);
    const auto values = filtered(row[i], a, b, c);
    for (std::size_t f = 0; f < 5; ++f)
      cost[f] += std::abs(int(std::int8_t(values[f])));
  }
  std::size_t best = 0;
  for (std::size_t f = 1; f < 5; ++f)
    if (cost[f] < cost[best])
      best = f;
  out[0] = std::uint8_t(best);
  for (std::size_t i = 0; i < row_bytes; ++i) {
    const auto [a, b, c] = neighbours(i);
    out[1 + i] = filtered(row[i], a, b, c)[best];
  }
}

/// `data` deflated as raw deflate blocks, ended by a sync flush (byte-aligned, so the next
/// segment's blocks can follow) or, for the image's last segment, a finish.
std::vector<std::uint8_t> deflate_segment(const std::vector<std::uint8_t>& data, bool last,
                                          const std::filesystem::path& path) {
  z_stream stream{};
  TEXSIM_VERIFY(deflateInit2(&stream, kDeflateLevel, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) ==
                    Z_OK,
                path.string() << ": zlib cannot start deflating");
  std::vector<std::uint8_t> out(deflateBound(&stream, uLong(data.size())) + 64);
  stream.next_in = const_cast<Bytef*>(data.data());
  stream.avail_in = uInt(data.size());
  stream.next_out = out.data();
  stream.avail_out = uInt(out.size());
  const int flush = last ? Z_FINISH : Z_SYNC_FLUSH;
  for (;;) {
    const int status = deflate(&stream, flush);
    const bool done = last ? status == Z_STREAM_END : stream.avail_in == 0 && stream.avail_out > 0;
    if (done)
      break;
    TEXSIM_VERIFY(status == Z_OK || status == Z_BUF_ERROR,
                  path.string() << ": zlib deflate failed (" << status << ")");
    const std::size_t used = out.size() - stream.avail_out;
    out.resize(2 * out.size());
    stream.next_out = out.data() + used;
    stream.avail_out = uInt(out.size() - used);
  }
  out.resize(out.size() - stream.avail_out);
  deflateEnd(&stream);
  return out;
}

void append_u32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(std::uint8_t(value >> shift));
}

/// A PNG chunk: length, type, data, CRC-32 of type and data.
void append_chunk(std::vector<std::uint8_t>& out, const char (&type)[5],
                  const std::vector<std::uint8_t>& data) {
  append_u32(out, std::uint32_t(data.size()));
  const auto start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  append_u32(out, std::uint32_t(crc32(0, out.data() + start, uInt(out.size() - start))));
}

/// One segment's share of the zlib stream's Adler-32 sum.
struct SegmentSum {
  std::uint64_t length = 0; ///< uncompressed (filtered) bytes
  std::uint32_t adler = 0;
};

struct CompressedRows {
  std::vector<std::uint8_t> chunks; ///< one IDAT chunk per segment, in row order
  std::vector<SegmentSum> sums;
};

CompressedRows compress_rows(const std::filesystem::path& path, int width, int height,
                             PngPixels pixels, const PngRows& rows, int segment_rows) {
  const int bpp = bytes_per_pixel(pixels);
  const auto row_bytes = std::size_t(width) * std::size_t(bpp);
  TEXSIM_VERIFY(rows.pixels.size() == std::size_t(rows.count) * row_bytes &&
                    (rows.first_row == 0 || rows.count == 0 || rows.above.size() == row_bytes),
                path.string() << ": rows " << rows.first_row << " .. "
                              << rows.first_row + rows.count - 1 << " given as "
                              << rows.pixels.size() << " bytes with " << rows.above.size()
                              << " above, for rows of " << row_bytes << " bytes");
  // Segments: [starts[s], starts[s + 1]) in rows of this rank.
  std::vector<int> starts{rows.first_row};
  for (int y = rows.first_row + 1; y < rows.first_row + rows.count; ++y)
    if (y % segment_rows == 0)
      starts.push_back(y);
  starts.push_back(rows.first_row + rows.count);
  const auto segments = rows.count > 0 ? starts.size() - 1 : 0;
  std::vector<std::vector<std::uint8_t>> chunks(segments);
  std::vector<SegmentSum> sums(segments);
  const std::vector<std::uint8_t> zero_row(row_bytes, 0);
  const auto row_at = [&](int y) {
    if (y < rows.first_row)
      return y < 0 ? zero_row.data() : rows.above.data();
    return rows.pixels.data() + std::size_t(y - rows.first_row) * row_bytes;
  };
  std::string failure;
#pragma omp parallel for schedule(dynamic)
  for (std::size_t s = 0; s < segments; ++s) {
    try {
      std::vector<std::uint8_t> filtered_rows(std::size_t(starts[s + 1] - starts[s]) *
                                              (row_bytes + 1));
      for (int y = starts[s]; y < starts[s + 1]; ++y)
        filter_row(row_at(y), row_at(y - 1), row_bytes, bpp,
                   filtered_rows.data() + std::size_t(y - starts[s]) * (row_bytes + 1));
      TEXSIM_VERIFY(filtered_rows.size() < std::size_t(UINT32_MAX),
                    path.string() << ": a PNG segment above 4 GiB; use fewer rows per segment");
      sums[s] = {filtered_rows.size(),
                 std::uint32_t(adler32(1, filtered_rows.data(), uInt(filtered_rows.size())))};
      append_chunk(chunks[s], "IDAT",
                   deflate_segment(filtered_rows, starts[s + 1] == height, path));
    } catch (const std::exception& error) {
#pragma omp critical(texsim_png_failure)
      if (failure.empty())
        failure = error.what();
    }
  }
  TEXSIM_VERIFY(failure.empty(), failure);
  CompressedRows compressed;
  for (const auto& chunk : chunks)
    compressed.chunks.insert(compressed.chunks.end(), chunk.begin(), chunk.end());
  compressed.sums = std::move(sums);
  return compressed;
}

/// Signature, IHDR and the zlib header; the compressed rows; the Adler-32 sum and IEND.
std::vector<std::uint8_t> png_file(int width, int height, PngPixels pixels,
                                   const std::vector<std::uint8_t>& chunks,
                                   const std::vector<SegmentSum>& sums) {
  std::vector<std::uint8_t> file{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  append_u32(header, std::uint32_t(width));
  append_u32(header, std::uint32_t(height));
  const bool rgb = pixels == PngPixels::rgb8;
  // bit depth, colour type (2 RGB, 0 grey), compression, filter method, no interlace
  header.insert(header.end(), {std::uint8_t(rgb ? 8 : 16), std::uint8_t(rgb ? 2 : 0), 0, 0, 0});
  append_chunk(file, "IHDR", header);
  // zlib header: deflate with a 32 KiB window, "fast" level, check bits making it a multiple of 31.
  const unsigned method = 0x78, level_flags = 0x40;
  append_chunk(
      file, "IDAT",
      {std::uint8_t(method), std::uint8_t(level_flags + 31 - (method << 8 | level_flags) % 31)});
  file.insert(file.end(), chunks.begin(), chunks.end());
  uLong adler = adler32(0, nullptr, 0);
  for (const auto& sum : sums)
    adler = adler32_combine(adler, sum.adler, z_off_t(sum.length));
  std::vector<std::uint8_t> trailer;
  append_u32(trailer, std::uint32_t(adler));
  append_chunk(file, "IDAT", trailer);
  append_chunk(file, "IEND", {});
  return file;
}

} // namespace

void write_parallel_png(const par::Comm& comm, const std::filesystem::path& path, int width,
                        int height, PngPixels pixels, const PngRows& rows, int segment_rows,
                        int root) {
  TEXSIM_VERIFY(width > 0 && height > 0 && segment_rows > 0,
                path.string() << ": PNG of " << width << " x " << height
                              << " pixels in segments of " << segment_rows << " rows");
  std::vector<int> ranges(2 * std::size_t(comm.size));
  const int mine[2] = {rows.first_row, rows.count};
  MPI_Allgather(mine, 2, MPI_INT, ranges.data(), 2, MPI_INT, comm.raw);
  int next_row = 0;
  for (int r = 0; r < comm.size; ++r) {
    TEXSIM_VERIFY(ranges[2 * std::size_t(r)] == next_row || ranges[2 * std::size_t(r) + 1] == 0,
                  path.string() << ": rank " << r << " holds rows from "
                                << ranges[2 * std::size_t(r)] << ", expected " << next_row);
    next_row += ranges[2 * std::size_t(r) + 1];
  }
  TEXSIM_VERIFY(next_row == height,
                path.string() << ": the ranks hold " << next_row << " of " << height << " rows");
  CompressedRows compressed;
  par::run_collectively(
      comm, [&] { compressed = compress_rows(path, width, height, pixels, rows, segment_rows); });
  const auto chunks =
      par::gather_to_root(comm, std::span<const std::uint8_t>(compressed.chunks), root);
  const auto sums = par::gather_to_root(comm, std::span<const SegmentSum>(compressed.sums), root);
  par::run_collectively(comm, [&] {
    if (comm.rank != root)
      return;
    const auto file = png_file(width, height, pixels, chunks, sums);
    if (path.has_parent_path())
      std::filesystem::create_directories(path.parent_path());
    write_atomically(path,
                     std::string_view(reinterpret_cast<const char*>(file.data()), file.size()));
  });
}

} // namespace texsim::io
