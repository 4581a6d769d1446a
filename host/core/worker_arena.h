// The worker threads of one parallel job: a TBB arena of `threads` workers (0: all cores).
// TBB caps its workers at the cores unless the cap is raised, so more threads than cores,
// when asked for (--threads), ran fewer and printed a warning, even under -q.
#pragma once

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <optional>
#include <utility>

namespace zz {

// The workers `threads` asks for (0: all the cores this process may run on, which TBB
// reads from its CPU affinity, so taskset, cpusets and Slurm's binding are obeyed; the
// count std::thread::hardware_concurrency gives is the machine's).
inline int worker_threads(int threads) { return threads > 0 ? threads : tbb::this_task_arena::max_concurrency(); }

class WorkerArena {
 public:
  explicit WorkerArena(int threads)
      : threads_(worker_threads(threads)),
        allow_(raised_cap(threads_)),
        arena_(threads_) {}

  int threads() const { return threads_; }
  template <class F>
  void execute(F&& f) {
    arena_.execute(std::forward<F>(f));
  }

 private:
  static std::optional<tbb::global_control> raised_cap(int threads) {
    if (threads <= int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)))
      return std::nullopt;
    return std::optional<tbb::global_control>(std::in_place, tbb::global_control::max_allowed_parallelism,
                                              size_t(threads));
  }

  int threads_;
  std::optional<tbb::global_control> allow_;  // before the arena, which it must outlive
  tbb::task_arena arena_;
};

}  // namespace zz
