// libsyrof_app.so's binding for the app host (platform_binding.h): one
// CAbiApp and one Platform per process, since a host runs one robot.
#include "platform_binding.h"

#include <cstdlib>
#include <new>
#include <span>
#include <string_view>

#include "syrof/app/c_abi_app.h"

namespace {

class HostPlatform final : public syrof::app::Platform {
 public:
  HostPlatform(syrof_internal_payload_sink sink, syrof_internal_parameter_source parameters,
               syrof_internal_parameter_source inputs, void* context, syrof_queries_workspace* workspace)
      : sink_(sink), parameters_(parameters), inputs_(inputs), context_(context), workspace_(workspace) {}

  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override {
    return static_cast<syrof_app_status>(sink_(context_, payload.data(), payload.size()));
  }
  syrof_queries_workspace* queries_workspace() override { return workspace_; }
  syrof_app_status AppParameter(std::string_view name, double& value) override {
    return static_cast<syrof_app_status>(parameters_(context_, name.data(), name.size(), &value));
  }
  syrof_app_status AppInput(std::string_view name, double& value) override {
    return static_cast<syrof_app_status>(inputs_(context_, name.data(), name.size(), &value));
  }

 private:
  syrof_internal_payload_sink sink_;
  syrof_internal_parameter_source parameters_;
  syrof_internal_parameter_source inputs_;
  void* context_;
  syrof_queries_workspace* workspace_;
};

// Static storage: the host binds once, before its callback filter forbids
// nothing but allocation (allocation stays allowed; this is just simpler).
alignas(HostPlatform) unsigned char platform_storage[sizeof(HostPlatform)];
alignas(syrof::app::CAbiApp) unsigned char app_storage[sizeof(syrof::app::CAbiApp)];
HostPlatform* platform = nullptr;
syrof::app::CAbiApp* bound_app = nullptr;

}  // namespace

extern "C" int syrof_internal_host_bind(const syrof_app_descriptor* descriptor, syrof_internal_payload_sink sink,
                                        syrof_internal_parameter_source parameters,
                                        syrof_internal_parameter_source inputs, void* context) {
  const syrof::app::DescriptorError error = syrof::app::Validate(descriptor);
  if (error != syrof::app::DescriptorError::kOk) return static_cast<int>(error);
  if (sink == nullptr || parameters == nullptr || inputs == nullptr || bound_app != nullptr) return static_cast<int>(syrof::app::DescriptorError::kNull);
  void* memory = std::aligned_alloc(syrof_queries_workspace_alignment(),
                                    (syrof_queries_workspace_size() + syrof_queries_workspace_alignment() - 1) /
                                        syrof_queries_workspace_alignment() * syrof_queries_workspace_alignment());
  syrof_queries_workspace* workspace = nullptr;
  if (memory == nullptr ||
      syrof_queries_workspace_init(memory, syrof_queries_workspace_size(), &workspace) != SYROF_QUERIES_OK) {
    return static_cast<int>(syrof::app::DescriptorError::kNull);
  }
  platform = new (platform_storage) HostPlatform(sink, parameters, inputs, context, workspace);
  bound_app = new (app_storage) syrof::app::CAbiApp(*descriptor);
  return 0;
}

extern "C" uint8_t syrof_internal_host_init(const syrof_app_info* info) {
  uint8_t global_state = 0;
  (void)bound_app->Init(*info, *platform, global_state);  // a C app's call is always ok
  return global_state;
}

extern "C" uint8_t syrof_internal_host_new_round(syrof_car_command* command, const syrof_ldmap* ldmap,
                                                 uint8_t global_state, uint32_t clock_ms) {
  (void)bound_app->NewRound(*command, *ldmap, global_state, clock_ms);
  return global_state;
}

extern "C" uint8_t syrof_internal_host_end_of_round(const syrof_ldmap* ldmap, uint8_t global_state,
                                                    uint32_t clock_ms) {
  (void)bound_app->EndOfRound(*ldmap, global_state, clock_ms);
  return global_state;
}
