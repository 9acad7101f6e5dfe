#pragma once
// The message of an expected exception, for tests that check what an error says.

#include <gtest/gtest.h>

#include <string>

namespace ocg::testing {

// The message of the exception of type Error that call throws; fails the test otherwise.
template <typename Error, typename Call>
std::string ErrorOf(Call call) {
  try {
    call();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no error of the expected type";
  return {};
}

}  // namespace ocg::testing
