#pragma once
/// Writing output files atomically. Every file texsim writes is first written in full under a
/// temporary name in its own directory, `<name>.tmp-<pid>`, flushed to disk (fsync), renamed over
/// its final name, and the directory entry flushed too. A job killed at any moment therefore
/// leaves either the previous file or the complete new one at the final name, never a truncated
/// file that looks valid; ParaView following a running job or a restart never reads half a file.
///
///   write_atomically(path, text);                        // contents held in memory
///   write_atomically(path, [&](const fs::path& temporary) {
///     writer->SetFileName(temporary.c_str());            // a library that needs a path
///     writer->Write();
///   });
///
/// Lives in core, the lowest layer, because writers in vol/img (OpenVDB, VTK image data, HDF5
/// grids, PNG) as well as io and the pipelines' caches use it.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace texsim {

/// `<directory>/<name>.tmp-<process_id>`: the name `path` has while that process writes it.
std::filesystem::path temporary_path_of(const std::filesystem::path& path, long process_id);

/// The temporary name of `path` for the calling process (its pid).
std::filesystem::path temporary_path_of(const std::filesystem::path& path);

/// The final file name a temporary name stands for ("a.vtu" for "a.vtu.tmp-1234"), or nothing
/// if `file_name` is not of the form `<name>.tmp-<digits>`.
std::optional<std::string> final_name_of_temporary(const std::string& file_name);

/// Flushes the complete file `temporary` to disk, renames it over `path` and flushes `path`'s
/// directory, so that after a crash the directory holds the new file under its final name. On
/// failure removes `temporary` and throws texsim::Error naming `path`. Not collective.
void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path);

/// Runs `write(temporary)`, which must create the complete file at the path it is given (and
/// close it), then commits it over `path` (see commit_temporary). If `write` throws, the
/// temporary is removed, the previous file at `path` (if any) is left as it was, and the
/// exception passes on unchanged; writers name `path`, not the temporary, in their messages.
/// Not collective.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);

/// Writes `contents` to `path` atomically as above. Throws texsim::Error naming `path` if the
/// file cannot be written. Not collective.
void write_atomically(const std::filesystem::path& path, std::string_view contents);

/// Receives the parts of a text, in order.
using TextSink = std::function<void(std::string_view part)>;

/// Writes to `path` atomically, as above, the parts `produce` passes to `emit` in order, each
/// written as it comes: for texts too large to hold whole (a large mesh as OBJ). Throws
/// texsim::Error naming `path` if the file cannot be written. Not collective.
void write_atomically_in_parts(const std::filesystem::path& path,
                               const std::function<void(const TextSink& emit)>& produce);

} // namespace texsim
