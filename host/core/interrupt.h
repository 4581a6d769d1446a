// SIGINT / SIGTERM (and SIGHUP, SIGQUIT alike): a render stops promptly and no partial
// output is left behind.
//
// While a cancellable phase runs (a CancellableScope: the tile scheduler polls
// interrupt_flag()), a signal only sets the flag and the code unwinds normally (the
// caller throws Interrupted). At any other moment (loading, writing an image through a
// library that cannot be stopped) the handler removes the temporaries being written
// (atomic_file.h), prints one line and exits at once. The exit status is 128 + signal:
// 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP. SIGXFSZ and SIGPIPE are ignored: a
// write past the file-size limit (EFBIG) or into a closed pipe (EPIPE) fails and is
// reported as a failed output.
#pragma once

#include <atomic>

namespace zz {

// Thrown (not a std::exception, so a batch's per-job error handling lets it through)
// after a cancellable phase was interrupted.
struct Interrupted {
  int signal;
};

void install_interrupt_handlers();

// Set by the handler during a cancellable phase.
const std::atomic<bool>& interrupt_flag();

// Throws Interrupted if a signal arrived.
void throw_if_interrupted();

// The one line printed for a signal, e.g. "zigzag: interrupted (SIGINT)".
const char* interrupt_message(int signal);

class CancellableScope {
 public:
  CancellableScope();
  ~CancellableScope();
  CancellableScope(const CancellableScope&) = delete;
  CancellableScope& operator=(const CancellableScope&) = delete;
};

}  // namespace zz
