// The sensor link's payloads (radio_link.h: kImu, kFlow, kUwb, kDrive) to
// and from the messages the estimator and the motion task use
// (estimation/messages.h, motion/drive.h), so both ends of the emulated
// swarm's sensor link convert the same way (docs/radio-link.md, "The sensor
// link"). The wire carries no timestamps: the receiver stamps each reading
// (or command) with its own clock when it arrives, as a driver stamps a
// sample when it reads it.
#pragma once

#include <cstdint>

#include "syrof/estimation/messages.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/motion/drive.h"

namespace syrof::firmware::drivers {

ImuPayload ToPayload(const estimation::ImuReading& reading);
/// An interval of 0 becomes 1 ns, one above 2^32 - 1 ns is clamped.
FlowPayload ToPayload(const estimation::FlowReading& reading);
/// Ranges rounded to whole mm; a range that is not finite, negative or above
/// 65.535 m is sent as not valid (its bit cleared, 0 mm).
UwbPayload ToPayload(const estimation::UwbReading& reading);
/// A command with a non-finite field becomes a stop (all zero, same kind).
DrivePayload ToPayload(const motion::DriveCommand& command);

estimation::ImuReading ToReading(const ImuPayload& payload, int64_t timestamp_ns);
estimation::FlowReading ToReading(const FlowPayload& payload, int64_t timestamp_ns);
/// Ranges whose bit is clear are 0.
estimation::UwbReading ToReading(const UwbPayload& payload, int64_t timestamp_ns);
motion::DriveCommand ToCommand(const DrivePayload& payload, int64_t timestamp_ns);

}  // namespace syrof::firmware::drivers
