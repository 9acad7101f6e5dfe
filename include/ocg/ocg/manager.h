#pragma once
// OcgManager: runs the OCG change detector on its own thread, fed one keyframe
// observation at a time through a bounded queue, or synchronously in the caller's
// thread in sequential mode (bit-for-bit reproducible runs).
//
// Threading contract:
//  - Submit() and Shutdown(): one producer thread (the object layer / tracking).
//  - Snapshot(), Status(), Removals(), GraphJson(), Pending(): any thread, any time;
//    they see the state after a whole keyframe, never half of one.
//  - The removal callback runs on the worker thread (in sequential mode: inside
//    Submit(), on the caller's thread), after the keyframe is fully processed and
//    without the manager's lock held, so it may call the readers above.
//  - Set the callback before the first Submit().
// An exception thrown while processing stops the worker; Submit() and Shutdown()
// rethrow it on the producer's thread.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ocg/ocg/change_detector.h"

namespace ocg {

struct MapFileAccess;

class OcgManager {
 public:
  using RemovalCallback = std::function<void(const KeyframeResult&)>;

  // queue_capacity: keyframes waiting before Submit() blocks (back-pressure: keyframes
  // are never dropped).
  OcgManager(OcgOptions options, bool sequential, std::size_t queue_capacity = 32);
  ~OcgManager();
  OcgManager(const OcgManager&) = delete;
  OcgManager& operator=(const OcgManager&) = delete;

  void SetRemovalCallback(RemovalCallback callback);
  void Submit(KeyframeObservation observation);
  // Processes everything queued, then stops the worker. Idempotent.
  void Shutdown();
  // Blocks until every submitted keyframe is processed.
  void WaitUntilIdle();
  // ObjectChangeDetector::StartSession / EndSession, after every submitted keyframe
  // (producer thread). EndSession's removals go to the callback like a keyframe's, on
  // the producer's thread.
  void StartSession();
  void EndSession(const ObjectChangeDetector::SuccessorCheck& may_have_become = {});

  std::vector<ObjectStatus> Snapshot() const;
  std::optional<ObjectStatus> Status(ObjectId id) const;
  std::vector<RemovalEvent> Removals() const;
  std::string GraphJson() const;
  std::size_t Pending() const;
  bool sequential() const { return sequential_; }

 private:
  friend struct MapFileAccess;  // map files (src/app/object_map_file.cc)
  void WorkerLoop();
  void ProcessOne(const KeyframeObservation& observation);
  template <typename Step>
  void Publish(Step&& step);
  void RethrowWorkerError();

  const bool sequential_;
  const std::size_t capacity_;
  RemovalCallback callback_;

  mutable std::mutex state_mutex_;  // guards detector_ and removals_
  ObjectChangeDetector detector_;
  std::vector<RemovalEvent> removals_;

  mutable std::mutex queue_mutex_;  // guards the fields below
  std::condition_variable queue_changed_;
  std::deque<KeyframeObservation> queue_;
  std::size_t in_progress_ = 0;
  bool stopping_ = false;
  std::exception_ptr worker_error_;
  std::thread worker_;
};

}  // namespace ocg
