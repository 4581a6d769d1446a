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
#include <string>

namespace zz {

// Calls write(temporary) and then publishes the temporary as `target`. The target's
// directory is created if needed. If `write` throws, or anything fails, the temporary is
// removed, the target is left untouched, and zz::Error (or write's exception) propagates.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temporary)>& write);

// Text (e.g. JSON) written atomically.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

// Async-signal-safe: removes every temporary being written right now (for a signal
// handler that is about to _exit).
void remove_temporaries_from_signal_handler();

}  // namespace zz
