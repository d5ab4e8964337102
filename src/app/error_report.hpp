#pragma once
/// How a failed run ends: one message and exit code 2 (bad input, out of memory) or 1 (internal
/// failure) when every rank failed, or MPI_Abort naming the rank when only some did.
#include "par/comm.hpp"

#include <exception>
#include <string>

namespace texsim::app {

/// Decides, after an exception, whether every rank failed. Owns a duplicate of the world
/// communicator, so its agreement cannot be confused with a collective call another rank is
/// still waiting in.
class ErrorReport {
public:
  /// Collective over `world`.
  explicit ErrorReport(const par::Comm& world);
  ~ErrorReport();
  ErrorReport(const ErrorReport&) = delete;
  ErrorReport& operator=(const ErrorReport&) = delete;

  /// Called by every failing rank with the caught exception. When every rank of the job calls it
  /// within a few seconds (an error every rank raised, collectively or each on its own), the
  /// lowest rank with the worst failure prints "texsim: error: <message>" and all return its exit
  /// code. Otherwise this rank prints "texsim: error on rank N: ..." and aborts the job, so the
  /// ranks still waiting in a collective call cannot hang.
  int finish(const std::exception_ptr& error) const;

private:
  par::Comm world_;
  MPI_Comm agreement_ = MPI_COMM_NULL;
};

/// The message with every word longer than 200 characters (a file name pasted by mistake)
/// shortened around its middle.
std::string with_long_words_shortened(const std::string& message);

} // namespace texsim::app
