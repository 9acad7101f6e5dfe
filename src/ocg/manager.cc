#include "ocg/ocg/manager.h"

#include <stdexcept>

#include "ocg/core/thread_name.h"

namespace ocg {

OcgManager::OcgManager(OcgOptions options, bool sequential, std::size_t queue_capacity)
    : sequential_(sequential),
      capacity_(queue_capacity == 0 ? 1 : queue_capacity),
      detector_(std::move(options)) {
  if (!sequential_) {
    worker_ = std::thread([this] {
      NameThisThread("ocg");
      WorkerLoop();
    });
  }
}

OcgManager::~OcgManager() {
  try {
    Shutdown();
  } catch (...) {
    // A worker error was already reported to the producer, or nobody is left to hear it.
  }
}

void OcgManager::SetRemovalCallback(RemovalCallback callback) { callback_ = std::move(callback); }

// step runs on the detector under state_mutex_; its removals are recorded there and
// reach the callback after the lock is released.
template <typename Step>
void OcgManager::Publish(Step&& step) {
  KeyframeResult result;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    result = step();
    removals_.insert(removals_.end(), result.removed.begin(), result.removed.end());
  }
  if (callback_ && !result.removed.empty()) callback_(result);
}

void OcgManager::ProcessOne(const KeyframeObservation& observation) {
  Publish([&] { return detector_.Process(observation); });
}

void OcgManager::RethrowWorkerError() {
  if (worker_error_) std::rethrow_exception(worker_error_);
}

void OcgManager::Submit(KeyframeObservation observation) {
  if (sequential_) {
    ProcessOne(observation);
    return;
  }
  std::unique_lock<std::mutex> lock(queue_mutex_);
  queue_changed_.wait(lock,
                      [&] { return queue_.size() < capacity_ || worker_error_ || stopping_; });
  RethrowWorkerError();
  if (stopping_) throw std::logic_error("OcgManager::Submit after Shutdown");
  queue_.push_back(std::move(observation));
  queue_changed_.notify_all();
}

void OcgManager::WorkerLoop() {
  for (;;) {
    KeyframeObservation observation;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      queue_changed_.wait(lock, [&] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;  // stopping, and drained
      observation = std::move(queue_.front());
      queue_.pop_front();
      ++in_progress_;
      queue_changed_.notify_all();  // room for a blocked producer
    }
    try {
      ProcessOne(observation);
    } catch (...) {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      worker_error_ = std::current_exception();
      queue_.clear();
      in_progress_ = 0;
      queue_changed_.notify_all();
      return;
    }
    std::lock_guard<std::mutex> lock(queue_mutex_);
    --in_progress_;
    queue_changed_.notify_all();
  }
}

void OcgManager::WaitUntilIdle() {
  if (sequential_) return;
  std::unique_lock<std::mutex> lock(queue_mutex_);
  queue_changed_.wait(lock, [&] { return (queue_.empty() && in_progress_ == 0) || worker_error_; });
  RethrowWorkerError();
}

void OcgManager::StartSession() {
  WaitUntilIdle();
  std::lock_guard<std::mutex> lock(state_mutex_);
  detector_.StartSession();
}

void OcgManager::EndSession(const ObjectChangeDetector::SuccessorCheck& may_have_become) {
  WaitUntilIdle();
  Publish([&] { return detector_.EndSession(may_have_become); });
}

void OcgManager::Shutdown() {
  if (sequential_) return;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    stopping_ = true;
    queue_changed_.notify_all();
  }
  if (worker_.joinable()) worker_.join();
  std::lock_guard<std::mutex> lock(queue_mutex_);
  RethrowWorkerError();
}

std::vector<ObjectStatus> OcgManager::Snapshot() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return detector_.Snapshot();
}

std::optional<ObjectStatus> OcgManager::Status(ObjectId id) const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return detector_.Status(id);
}

std::vector<RemovalEvent> OcgManager::Removals() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return removals_;
}

std::string OcgManager::GraphJson() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return detector_.ToJson();
}

std::size_t OcgManager::Pending() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return queue_.size() + in_progress_;
}

}  // namespace ocg
