#include "pbd/parallel/worker_pool.h"

#include <stdexcept>
#include <string>

namespace pbd {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1)
    throw std::invalid_argument("worker pool: expected at least 1 thread, got " +
                                std::to_string(threads));
  helpers_.reserve(std::size_t(threads - 1));
  for (int part = 1; part < threads; ++part)
    helpers_.emplace_back([this, part] { helperLoop(part); });
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& helper : helpers_)
    helper.join();
}

void WorkerPool::run(Task task, void* context) {
  if (helpers_.empty()) {
    task(context, 0);
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    context_ = context;
    pending_ = static_cast<int>(helpers_.size());
    ++generation_;
  }
  wake_.notify_all();
  task(context, 0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
}

void WorkerPool::helperLoop(int part) {
  std::uint64_t seen = 0;
  for (;;) {
    Task task = nullptr;
    void* context = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      task = task_;
      context = context_;
    }
    task(context, part);
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }
}

}  // namespace pbd
