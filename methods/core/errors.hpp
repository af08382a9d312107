/// Error types: every failure a user can cause names the input and the fix.
#pragma once
#include <stdexcept>
#include <string>

namespace mfv {

/// Bad input from a user: unknown name, out-of-range parameter, unreadable file.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A moment matrix or a global system that cannot be solved; the message names the point
/// or the system and the likely cause.
class SingularError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mfv
