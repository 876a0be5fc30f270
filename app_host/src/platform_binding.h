/* The app host's way into libsyrof_app.so: not part of the app API.
 *
 * syrof-app-host links libsyrof_app.so, as the student's library does, so
 * both see one copy of the platform's state. The host binds the loaded
 * descriptor and a payload sink here; the calls below then run the app
 * through core/app's CAbiApp, exactly as an in-process C app runs, and the
 * app's sendMessageData reaches the sink (the host records each call for the
 * reply frame), and its syrofAppParameter and syrofAppInput ask the sources (the host
 * answers from the parameters and inputs of the init request). The names start with syrof_internal_ so no app mistakes them
 * for the API. */
#ifndef SYROF_APP_HOST_PLATFORM_BINDING_H
#define SYROF_APP_HOST_PLATFORM_BINDING_H

#include <stddef.h>
#include <stdint.h>

#include "syrof/app.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Receives every payload the app's sendMessageData hands the platform
 * (NULL with a non-zero length never gets here) and answers as the robot
 * would (SYROF_APP_OK or SYROF_APP_PAYLOAD_TOO_LONG). */
typedef int (*syrof_internal_payload_sink)(void* context, const uint8_t* payload, size_t length);

/* Answers the app's syrofAppParameter (or syrofAppInput): `name` is
 * `length` bytes (already checked: not NULL, at most
 * SYROF_APP_MAX_PARAMETER_NAME_LENGTH, no NUL inside). Returns SYROF_APP_OK
 * with *value set, or SYROF_APP_NO_SUCH_PARAMETER (SYROF_APP_NO_SUCH_INPUT)
 * leaving it alone. */
typedef int (*syrof_internal_parameter_source)(void* context, const char* name, size_t length, double* value);

/* Checks `descriptor` (core/app Validate) and, when it is valid, makes it the
 * process's app. Returns the syrof::app::DescriptorError (0 is ok). Also sets
 * up the queries' workspace (allocates: call before the callback filter).
 * `parameters` answers syrofAppParameter, `inputs` syrofAppInput; `context`
 * goes to `sink`, `parameters` and `inputs`. */
int syrof_internal_host_bind(const syrof_app_descriptor* descriptor, syrof_internal_payload_sink sink,
                             syrof_internal_parameter_source parameters, syrof_internal_parameter_source inputs,
                             void* context);

/* The bound app's callbacks (through CAbiApp). */
uint8_t syrof_internal_host_init(const syrof_app_info* info);
uint8_t syrof_internal_host_new_round(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t global_state,
                                      uint32_t clock_ms);
uint8_t syrof_internal_host_end_of_round(const syrof_ldmap* ldmap, uint8_t global_state, uint32_t clock_ms);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif
