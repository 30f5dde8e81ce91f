#include "sim_test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "vaw/scene_loader.hpp"

namespace vaw::simtest {

std::vector<std::string> transitionNames(const sim::World& w, PartId part) {
  std::vector<std::string> out;
  for (const auto& t : w.transitions())
    if (t.part == part)
      out.push_back(std::string(interact::name(t.event)) + ":" + std::string(interact::name(t.to)));
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace vaw::simtest
