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
#include <optional>
#include <string>
#include <vector>

namespace zz {

class OutputSet;

// Calls write(temporary) and then publishes the temporary as `target` (output_target: a
// link's target; a stream gets the temporary's bytes). The temporary is written in the
// target's folder, a stream's in the system's temporary folder. The target's directory is
// created if needed; a write-protected target is refused (zz::Error). If `write` throws,
// or anything fails, the temporary is removed, the target is left untouched, and
// zz::Error (or write's exception) propagates. With `set`, the written temporary is
// staged in it instead, published by set->commit().
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
  // Writes the staged streams' bytes to them, then renames every other staged temporary
  // over its target, each in the order staged (a stream that fails so leaves every file
  // target as it was); throws Interrupted afterwards if a signal arrived meanwhile.
  void commit();

 private:
  struct Staged;
  std::vector<std::unique_ptr<Staged>> staged_;
};

// Where writing `path` lands: its symbolic links followed to the file they name (which may
// not exist yet), as cp, a shell's > and image writers do; `path` itself when it is none.
// An output given as a link replaces the link's target, never the link.
std::filesystem::path output_target(const std::filesystem::path& path);

// Whether `target` (followed: output_target) is an existing file the user protected from
// writing: one the caller may not write (access), or, as root, which may write anything,
// one with no write bit at all (rm's "write-protected regular file"). Such a file is
// refused, not replaced: renaming a temporary over it would defeat the protection.
bool write_protected(const std::filesystem::path& target);

// Whether `target` is, or links to, a device, pipe or socket (/dev/stdout, a FIFO), or names
// one of this process's open descriptors (own_descriptor): a stream, which receives the
// finished output's bytes instead of being replaced.
bool output_is_stream(const std::filesystem::path& target);

// The descriptor `target` names when it is one this process holds open: /dev/stdout,
// /dev/stderr, /dev/fd/N, /proc/self/fd/N, or a link to one of them. Such an output is
// written through that descriptor, as the shell set it up (`--stats /dev/stdout >> log`
// appends at its offset; reopening the name, or renaming over the file behind it, replaced
// what the log held).
std::optional<int> own_descriptor(const std::filesystem::path& target);

// What a stream is, whatever its name: "stream DEV:INODE" (/dev/stdout, /dev/fd/1 and a link
// to that pipe are one), or nullopt when `target` is no stream (output_is_stream).
std::optional<std::string> stream_identity(const std::filesystem::path& target);

// 64 random bits as 16 hex digits, for names no other process picks (getrandom;
// temporaries, the output folder's write probe).
std::string random_token();

// Async-signal-safe: removes every temporary being written right now (for a signal
// handler that is about to _exit).
void remove_temporaries_from_signal_handler();

}  // namespace zz
