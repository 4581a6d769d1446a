// Writing an output so that a crash, a kill or a full disk at any moment leaves either
// the old file or the complete new one, never a partial file: the bytes go to a
// temporary in the target's directory (same file system, so the rename is atomic),
// which is flushed to disk (fsync) and renamed over the target.
//
// Every output kind uses it: images (OpenImageIO writes to the temporary's name, which
// keeps the target's extension so the format is chosen the same way), stats JSON, AOVs.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace zz {

class OutputSet;

// Calls write(temporary) and then publishes the temporary as `target`. The target's
// directory is created if needed. If `write` throws, or anything fails, the temporary is
// removed, the target is left untouched, and zz::Error (or write's exception) propagates.
// With `set`, the written temporary is staged in it instead, published by set->commit().
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temporary)>& write,
                      OutputSet* set = nullptr);

// Text (e.g. JSON) written atomically (staged in `set` if given).
void write_text_atomically(const std::filesystem::path& target, const std::string& text, OutputSet* set = nullptr);

// The outputs of one job, published together: each is written in full to its temporary
// first, and only when every one was does commit() rename them over their targets. A job
// that fails half-way (a full disk at its third file) so leaves all of its targets as
// they were; the destructor removes the temporaries of a set never committed. A first
// SIGINT / SIGTERM during the renames waits for them (core/interrupt.h); a rename that
// fails (the target's folder changed since the outputs were checked) leaves the outputs
// before it published.
class OutputSet {
 public:
  OutputSet();
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  void stage(const std::filesystem::path& target,
             const std::function<void(const std::filesystem::path& temporary)>& write);
  // Renames every staged temporary over its target, in the order staged; throws
  // Interrupted afterwards if a signal arrived meanwhile.
  void commit();

 private:
  struct Staged;
  std::vector<std::unique_ptr<Staged>> staged_;
};

// 64 random bits as 16 hex digits, for names no other process picks (getrandom;
// temporaries, the output folder's write probe).
std::string random_token();

// Async-signal-safe: removes every temporary being written right now (for a signal
// handler that is about to _exit).
void remove_temporaries_from_signal_handler();

}  // namespace zz
