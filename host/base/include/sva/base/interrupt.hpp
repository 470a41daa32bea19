#pragma once
// Clean Ctrl-C: the CLI installs a SIGINT handler that only sets a flag; long
// loops poll it and throw sva::Interrupted, so destructors run, temporary files
// are removed and no partial output is left looking complete.
#include <sva/error.hpp>

namespace sva::util {

void install_interrupt_handler();
bool interrupted();
void request_interrupt();  // tests
void clear_interrupt();    // tests
inline void throw_if_interrupted() {
  if (interrupted()) throw Interrupted();
}

}  // namespace sva::util
