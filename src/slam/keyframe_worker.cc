#include "ocg/slam/keyframe_worker.h"

#include "ocg/core/thread_name.h"

namespace ocg {

KeyFrameWorker::KeyFrameWorker(std::size_t capacity,
                               std::function<void(const KeyFramePtr&)> process,
                               std::string thread_name)
    : capacity_(capacity), process_(std::move(process)), thread_name_(std::move(thread_name)) {}

KeyFrameWorker::~KeyFrameWorker() {
  try {
    Stop();
  } catch (...) {
    // Reported by an explicit Stop(), or the owner is unwinding from it.
  }
}

void KeyFrameWorker::Start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (thread_.joinable()) return;
  stopping_ = false;
  thread_ = std::thread([this] {
    NameThisThread(thread_name_);
    Run();
  });
}

void KeyFrameWorker::Insert(const KeyFramePtr& keyframe) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < capacity_ || failure_ != nullptr; });
  if (failure_) std::rethrow_exception(failure_);
  queue_.push_back(keyframe);
  changed_.notify_all();
}

bool KeyFrameWorker::Idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.empty() && !busy_;
}

std::size_t KeyFrameWorker::Waiting() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.size();
}

void KeyFrameWorker::Run() {
  for (;;) {
    KeyFramePtr keyframe;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;  // stopping and drained
      keyframe = queue_.front();
      queue_.pop_front();
      busy_ = true;
    }
    try {
      process_(keyframe);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      failure_ = std::current_exception();
      busy_ = false;
      queue_.clear();
      changed_.notify_all();
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    busy_ = false;
    changed_.notify_all();
  }
}

void KeyFrameWorker::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_) {
    std::exception_ptr failure = failure_;
    failure_ = nullptr;
    std::rethrow_exception(failure);
  }
}

}  // namespace ocg
