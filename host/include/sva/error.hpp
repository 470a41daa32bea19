#pragma once
// Errors a user can cause (bad files, bad options, bad values) are thrown as
// sva::Error with a message that names the file or value and what is wrong.
#include <stdexcept>
#include <string>

namespace sva {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown by long-running work when the user interrupts it (Ctrl-C).
class Interrupted : public Error {
 public:
  Interrupted() : Error("interrupted") {}
};

}  // namespace sva
