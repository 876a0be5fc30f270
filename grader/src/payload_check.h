// The grader's check of every payload a robot sets against the assignment's
// message format (`message:`, docs/grading.md "Mixed swarms"): an App that
// wraps the robot's app and sees each sendMessageData call on its way to
// the platform, refused ones (over 9 bytes) included. Internal to grader/.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "syrof/app/app.h"
#include "syrof/lab/message/message_format.h"

namespace syrof::grader::internal {

/// One robot's payloads that broke the format.
struct PayloadViolations {
  int count = 0;
  std::string first;  ///< "in init of epoch 0: 10 bytes, but the format has 2"
};

/// Wraps `app` so that every payload it sets is checked against `format`;
/// violations go to `violations`, which (like `format`) must outlive the
/// returned app and is written only from that app's calls.
std::unique_ptr<app::App> CheckPayloads(std::unique_ptr<app::App> app, const lab::message::MessageFormat& format,
                                        PayloadViolations& violations);

}  // namespace syrof::grader::internal
