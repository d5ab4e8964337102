#include "app/error_report.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "core/log.hpp"
#include "core/memory_budget.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <new>
#include <thread>

namespace texsim::app {
namespace {

/// How long a failing rank waits for the others to fail too before it aborts the job. Ranks that
/// raise the same error do so within milliseconds of each other.
constexpr std::chrono::seconds kAgreementWait{10};

struct Failure {
  int exit_code = 1;
  std::string message;
};

Failure describe(const std::exception_ptr& error, int rank) {
  try {
    std::rethrow_exception(error);
  } catch (const InputError& e) {
    return {2, e.what()};
  } catch (const Error& e) {
    return {1, e.what()};
  } catch (const std::bad_alloc&) {
    return {2, out_of_memory_message(rank)};
  } catch (const std::filesystem::filesystem_error& e) {
    // A path from the config or the command line that the file system refuses (too long, ...).
    return {2, e.what()};
  } catch (const std::exception& e) {
    return {1, std::string("internal error: ") + e.what()};
  } catch (...) {
    return {1, "internal error: unknown exception"};
  }
}

/// True when every rank reached the agreement barrier within kAgreementWait.
bool every_rank_failed(MPI_Comm agreement) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibarrier(agreement, &request);
  const auto deadline = std::chrono::steady_clock::now() + kAgreementWait;
  int done = 0;
  while (true) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done != 0 || std::chrono::steady_clock::now() > deadline)
      return done != 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

} // namespace

std::string with_long_words_shortened(const std::string& message) {
  constexpr std::size_t kLongWord = 200;
  std::string out;
  std::size_t pos = 0;
  while (pos < message.size()) {
    const std::size_t end = std::min(message.find_first_of(" \n\t'", pos), message.size());
    out += shortened(message.substr(pos, end - pos), kLongWord);
    if (end < message.size())
      out += message[end];
    pos = end + 1;
  }
  return out;
}

ErrorReport::ErrorReport(const par::Comm& world) : world_(world) {
  MPI_Comm_dup(world.raw, &agreement_);
}

ErrorReport::~ErrorReport() {
  if (agreement_ != MPI_COMM_NULL)
    MPI_Comm_free(&agreement_);
}

int ErrorReport::finish(const std::exception_ptr& error) const {
  const Failure failure = describe(error, world_.rank);
  const std::string message = with_long_words_shortened(failure.message);
  if (!every_rank_failed(agreement_)) {
    log::error_line(log::cat("texsim: error on rank ", world_.rank, ": ", message));
    MPI_Abort(world_.raw, failure.exit_code);
  }
  // Every rank is here: the lowest rank with the worst failure speaks for all.
  int worst = 0;
  MPI_Allreduce(&failure.exit_code, &worst, 1, MPI_INT, MPI_MAX, agreement_);
  const int candidate = failure.exit_code == worst ? world_.rank : world_.size;
  int speaker = 0;
  MPI_Allreduce(&candidate, &speaker, 1, MPI_INT, MPI_MIN, agreement_);
  if (world_.rank == speaker)
    log::error_line("texsim: error: " + message);
  return worst;
}

} // namespace texsim::app
