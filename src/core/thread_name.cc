#include "ocg/core/thread_name.h"

#if defined(__linux__)
#include <pthread.h>
#endif

namespace ocg {

namespace {
constexpr std::size_t kLinuxMaxThreadName = 15;  // 16 bytes with the terminating NUL
}  // namespace

void NameThisThread(const std::string& name) {
#if defined(__linux__)
  const std::string shortened = name.substr(0, kLinuxMaxThreadName);
  pthread_setname_np(pthread_self(), shortened.c_str());
#else
  (void)name;
#endif
}

std::string ThisThreadName() {
#if defined(__linux__)
  char buffer[kLinuxMaxThreadName + 1] = {};
  if (pthread_getname_np(pthread_self(), buffer, sizeof(buffer)) == 0) return buffer;
#endif
  return {};
}

}  // namespace ocg
