// The headers that most test programs parse, precompiled once for all of them
// (tests/CMakeLists.txt, OCG_TEST_PCH): parsing them was about half of a test file's
// compile time. Only third-party headers: a test still includes what it uses, and the
// project's own headers are compiled as each test includes them.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>
