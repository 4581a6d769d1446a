#include "core/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <cstring>

#include "core/atomic_file.h"

namespace zz {

namespace {

std::atomic<bool> g_flag{false};
std::atomic<int> g_signal{0};
std::atomic<int> g_cancellable{0};

void handle(int sig) {
  g_signal.store(sig);
  if (g_cancellable.load() > 0 && !g_flag.exchange(true)) return;  // the render unwinds
  // Not cancellable here (or a second signal): clean up and leave now.
  remove_temporaries_from_signal_handler();
  const char* msg = interrupt_message(sig);
  ssize_t ignored = ::write(STDERR_FILENO, msg, std::strlen(msg));
  ignored = ::write(STDERR_FILENO, "\n", 1);
  (void)ignored;
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = handle;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  // SIGHUP (a closed terminal, a dropped ssh session) and SIGQUIT end a run as SIGTERM
  // does; uncaught they left 30 MB temporaries behind.
  // A signal the parent set to be ignored stays ignored: `nohup` (SIGHUP), a shell's
  // background job (SIGINT, SIGQUIT).
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
    struct sigaction old {};
    if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(sig, &sa, nullptr);
  }
  // A warning printed to a closed pipe fails with EPIPE instead of killing the process
  // between writing its outputs and publishing them.
  ::signal(SIGPIPE, SIG_IGN);
  // A write past the file-size limit (ulimit -f) then fails with EFBIG, which the output
  // reports as any other failed write, instead of killing the process mid-file.
  ::signal(SIGXFSZ, SIG_IGN);
}

const std::atomic<bool>& interrupt_flag() { return g_flag; }

void throw_if_interrupted() {
  if (g_flag.load()) throw Interrupted{g_signal.load()};
}

const char* interrupt_message(int signal) {
  switch (signal) {
    case SIGTERM: return "zigzag: terminated (SIGTERM); no output was left half-written";
    case SIGHUP: return "zigzag: hung up (SIGHUP); no output was left half-written";
    case SIGQUIT: return "zigzag: quit (SIGQUIT); no output was left half-written";
    default: return "zigzag: interrupted (SIGINT); no output was left half-written";
  }
}

CancellableScope::CancellableScope() { ++g_cancellable; }
CancellableScope::~CancellableScope() { --g_cancellable; }

}  // namespace zz
