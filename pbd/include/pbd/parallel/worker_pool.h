// A fixed set of helper threads that run the parts of one task and wait for the next: the
// parallel collision detection's workers (collision_detection.h, `threads` > 1).
//
// run(task, context) calls task(context, part) for part = 0 … threads − 1, part 0 on the
// calling thread, and returns when every part has finished. The task is a plain function
// pointer with a context pointer: starting a task allocates nothing (no std::function), so a
// step that runs one stays free of heap allocation. Which thread runs which part is fixed, but
// nothing may depend on it: a task's parts write disjoint outputs, and the caller combines
// them in part order, so results do not depend on the thread count or on scheduling.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace pbd {

class WorkerPool {
 public:
  using Task = void (*)(void* context, int part);

  /// `threads` ≥ 1 parts per task; threads − 1 helper threads are started.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }
  /// Runs every part of `task` and returns when all have finished.
  void run(Task task, void* context);

 private:
  void helperLoop(int part);

  std::mutex mutex_;
  std::condition_variable wake_;  ///< a new task, or stop
  std::condition_variable done_;  ///< the last helper finished its part
  std::vector<std::thread> helpers_;
  std::uint64_t generation_ = 0;  ///< counts tasks; a helper runs each generation once
  int pending_ = 0;               ///< helpers still running the current task
  bool stop_ = false;
  Task task_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace pbd
