#pragma once
/// Capturing the message of the InputError a call throws, so tests can check what it names.
#include "core/error.hpp"

#include <string>

namespace texsim::test {

/// The message of the InputError `fn` throws, or "no InputError thrown" (which contains none of
/// the file names and phrases the tests look for) when it returns normally.
template <class Fn> std::string input_error_message(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError thrown";
}

} // namespace texsim::test
