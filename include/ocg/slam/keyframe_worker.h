#pragma once
// A thread that takes keyframes one at a time from a bounded queue and hands each to a
// function: the local mapping and loop closing threads.
//
// Threading: Start, Insert and Stop from one owner thread; Idle and Waiting from any
// thread. Insert blocks while the queue is full (no keyframe is ever dropped) and rethrows
// a failure of the worker; Stop finishes the queue, joins, and rethrows a failure once.

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "ocg/slam/map.h"

namespace ocg {

class KeyFrameWorker {
 public:
  // thread_name: what profilers and debuggers show for the thread (at most 15 characters).
  KeyFrameWorker(std::size_t capacity, std::function<void(const KeyFramePtr&)> process,
                 std::string thread_name);
  // Stops the thread; a failure not yet reported is dropped (the owner is unwinding).
  ~KeyFrameWorker();
  KeyFrameWorker(const KeyFrameWorker&) = delete;
  KeyFrameWorker& operator=(const KeyFrameWorker&) = delete;

  void Start();  // idempotent while running
  void Insert(const KeyFramePtr& keyframe);
  bool Idle() const;  // nothing queued, nothing being processed
  // Keyframes inserted and not yet taken by the worker (any thread): the one being
  // processed is not counted.
  std::size_t Waiting() const;
  void Stop();  // idempotent

 private:
  void Run();

  std::size_t capacity_;
  std::function<void(const KeyFramePtr&)> process_;
  std::string thread_name_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<KeyFramePtr> queue_;
  bool busy_ = false;
  bool stopping_ = false;
  std::exception_ptr failure_;
  std::thread thread_;
};

}  // namespace ocg
