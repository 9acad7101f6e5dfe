#include "ocg/optim/solver_logging.h"

#include <glog/logging.h>
#include <spdlog/spdlog.h>

#include <mutex>
#include <string_view>

namespace ocg {
namespace {

// Hands each glog line (Ceres writes its warnings through glog) to the project's logger,
// with the file and line that wrote it.
class SpdlogSink : public google::LogSink {
 public:
  void send(google::LogSeverity severity, const char* /*full_filename*/, const char* base_filename,
            int line, const google::LogMessageTime& /*time*/, const char* message,
            std::size_t message_len) override {
    const std::string_view text(message, message_len);
    switch (severity) {
      case google::GLOG_INFO:
        spdlog::debug("ceres ({}:{}): {}", base_filename, line, text);
        break;
      case google::GLOG_WARNING:
        spdlog::warn("ceres ({}:{}): {}", base_filename, line, text);
        break;
      default:
        spdlog::error("ceres ({}:{}): {}", base_filename, line, text);
        break;
    }
  }
};

}  // namespace

void RouteSolverLogging() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("ocg");
    FLAGS_logtostderr = false;
    FLAGS_alsologtostderr = false;
    // Only a fatal message (glog aborts after it) still reaches stderr directly.
    FLAGS_stderrthreshold = google::GLOG_FATAL;
    // No log files: an empty base name turns a severity's file off.
    for (const google::LogSeverity severity :
         {google::GLOG_INFO, google::GLOG_WARNING, google::GLOG_ERROR, google::GLOG_FATAL}) {
      google::SetLogDestination(severity, "");
    }
    static SpdlogSink sink;  // lives as long as glog may call it
    google::AddLogSink(&sink);
  });
}

}  // namespace ocg
