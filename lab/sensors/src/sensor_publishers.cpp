#include "syrof/lab/sensors/sensor_publishers.h"

namespace syrof::lab::sensors {

pubsub::BrokerError SensorPublishers::Advertise(pubsub::Broker& broker) {
  if (const pubsub::BrokerError error = imu_.Advertise(broker, estimation::kImuTopic);
      error != pubsub::BrokerError::kOk) {
    return error;
  }
  if (const pubsub::BrokerError error = flow_.Advertise(broker, estimation::kFlowTopic);
      error != pubsub::BrokerError::kOk) {
    return error;
  }
  return uwb_.Advertise(broker, estimation::kUwbTopic);
}

void SensorPublishers::Count(pubsub::BrokerError error) {
  if (error == pubsub::BrokerError::kOk) {
    ++published_;
  } else {
    ++failed_;
  }
}

void SensorPublishers::OnImu(const estimation::ImuReading& reading) { Count(imu_.Publish(reading)); }
void SensorPublishers::OnFlow(const estimation::FlowReading& reading) { Count(flow_.Publish(reading)); }
void SensorPublishers::OnUwb(const estimation::UwbReading& reading) { Count(uwb_.Publish(reading)); }

os::TaskConfig SimulatedSensorsTask::Config(int64_t period_ns) {
  return os::TaskConfig{"sensors.simulated", os::Trigger::periodic(period_ns),
                        registry::kSensorTaskPriority};
}

void SimulatedSensorsTask::Step(int64_t now_ns) { bank_.Sample(now_ns, trajectory_.At(now_ns), sink_); }

}  // namespace syrof::lab::sensors
