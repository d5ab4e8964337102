#pragma once
/// Turning a failure on some ranks into the same exception on every rank, so no rank waits forever
/// in a collective call that a failed rank will never reach.
#include "par/comm.hpp"

#include <functional>

namespace texsim::par {

/// Runs `work` on every rank. If it throws on any rank, every rank throws the same exception type
/// (InputError stays InputError) with the message of the lowest failing rank. Collective: `work`
/// must not itself wait on ranks that may have failed before reaching the same point.
void run_collectively(const Comm& comm, const std::function<void()>& work);

} // namespace texsim::par
