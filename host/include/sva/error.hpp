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

// The GPU was lost mid-work (VK_ERROR_DEVICE_LOST: a driver reset, a hang, a removed device). The recognizer that
// threw it cannot go on on that device; its readings so far are intact: save_session, make a new Engine (a new
// device) and restore_session onto a new Recognizer, which replays them bit for bit (docs/reliability.md).
class DeviceLost : public Error {
 public:
  using Error::Error;
};

}  // namespace sva
