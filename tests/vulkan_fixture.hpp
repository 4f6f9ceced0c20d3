// The Vulkan device fixture of the suites that run exports on a device
// (lavapipe needs no GPU): one device per suite, opened once and shared by its
// tests; every test of the suite skips, naming the reason, when no device can
// be opened or the device lacks what the suite needs. CI's sanitizer run
// filters these suites by name (^OnVulkan in .ci/run).
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "export/vulkan_runner.hpp"

namespace sglab::test {

// What a suite needs of the device.
enum class DeviceNeed { compute, float16 };

template <DeviceNeed Need>
class VulkanDeviceTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      device_ = new shader::vulkan::Device();
      if (Need == DeviceNeed::float16 && !device_->has_float16())
        skip_reason_ = device_->name() + " offers no shaderFloat16";
    } catch (const shader::vulkan::Unavailable& e) {
      skip_reason_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    delete device_;
    device_ = nullptr;
  }
  void SetUp() override {
    if (!skip_reason_.empty())
      GTEST_SKIP() << (Need == DeviceNeed::float16 ? "no Vulkan device with half arithmetic: "
                                                   : "no Vulkan device: ")
                   << skip_reason_;
  }
  static inline shader::vulkan::Device* device_ = nullptr;
  static inline std::string skip_reason_;
};

}  // namespace sglab::test

// The suite names are the ones CI filters on.
using OnVulkan = sglab::test::VulkanDeviceTest<sglab::test::DeviceNeed::compute>;
using OnVulkanHalf = sglab::test::VulkanDeviceTest<sglab::test::DeviceNeed::float16>;
