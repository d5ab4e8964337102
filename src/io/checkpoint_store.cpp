#include "io/checkpoint_store.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "io/checkpoint_format.hpp"
#include "io/hdf5_attribute.hpp"
#include "io/hdf5_file.hpp"
#include "par/collective.hpp"

#include <optional>

namespace texsim::io {
namespace {

/// The config hash stored in a checkpoint, or nothing if the file cannot be read.
std::optional<std::string> stored_config_hash(const std::filesystem::path& path) {
  try {
    const par::Hdf5Handle file = open_serial_file(path);
    const auto value = read_attribute(file.get(), config_hash_attribute, path);
    if (const auto* hash = std::get_if<std::string>(&value))
      return *hash;
  } catch (const Error&) {
  }
  return std::nullopt;
}

} // namespace

CheckpointStore::CheckpointStore(const par::Comm& comm, std::filesystem::path directory,
                                 std::string config_hash, int keep_last)
    : comm_(comm), directory_(std::move(directory)), config_hash_(std::move(config_hash)),
      keep_last_(keep_last) {
  par::run_collectively(comm_, [&] {
    TEXSIM_VERIFY(keep_last_ >= 1, "checkpoint keep_last must be at least 1, got " << keep_last_);
    if (!comm_.is_root())
      return;
    std::error_code error;
    std::filesystem::create_directories(directory_, error);
    if (error)
      TEXSIM_INPUT_ERROR(directory_.string()
                         << ": cannot create the checkpoint directory (" << error.message() << ")");
    refuse_other_configuration();
    remove_uncommitted_checkpoints(directory_);
  });
}

void CheckpointStore::refuse_other_configuration() const {
  const auto existing = list_checkpoint_steps(directory_);
  for (auto step = existing.rbegin(); step != existing.rend(); ++step) {
    const auto path = path_of(*step);
    const auto hash = stored_config_hash(path);
    if (!hash)
      continue;
    if (*hash != config_hash_)
      TEXSIM_INPUT_ERROR(path.string() << ": written by a different configuration (config hash "
                                       << *hash << ", this run " << config_hash_
                                       << "); start a fresh output.dir or use the matching config");
    return;
  }
}

CheckpointWriter CheckpointStore::begin(std::int64_t step) const {
  return CheckpointWriter(comm_, directory_, config_hash_, step, keep_last_);
}

std::vector<std::int64_t> CheckpointStore::steps() const {
  std::vector<std::int64_t> found;
  if (comm_.is_root())
    found = list_checkpoint_steps(directory_);
  int count = static_cast<int>(found.size());
  MPI_Bcast(&count, 1, MPI_INT, 0, comm_.raw);
  found.resize(count);
  MPI_Bcast(found.data(), count, MPI_INT64_T, 0, comm_.raw);
  return found;
}

std::filesystem::path CheckpointStore::path_of(std::int64_t step) const {
  return directory_ / checkpoint_file_name(step);
}

ResolvedCheckpoint CheckpointStore::resolve(const std::string& spec) const {
  if (spec != "latest")
    return {open(spec), {}};
  std::vector<SkippedCheckpoint> skipped;
  const auto existing = steps();
  for (auto step = existing.rbegin(); step != existing.rend(); ++step) {
    const auto path = path_of(*step);
    try {
      return {open(path), std::move(skipped)};
    } catch (const InputError& e) {
      skipped.push_back({path, e.what()});
    }
  }
  std::ostringstream message;
  message << directory_.string() << ": no usable checkpoint to restart from";
  for (const auto& entry : skipped)
    message << "\n  skipped " << entry.reason;
  throw InputError(message.str());
}

CheckpointReader CheckpointStore::open(const std::filesystem::path& path) const {
  return CheckpointReader(comm_, path, config_hash_);
}

CheckpointReader CheckpointStore::resolve_for_restart(const std::string& spec) const {
  auto found = resolve(spec);
  for (const auto& skipped : found.skipped)
    log::warn("skipped checkpoint " + skipped.path.string() + ": " + skipped.reason);
  return std::move(found.reader);
}

} // namespace texsim::io
