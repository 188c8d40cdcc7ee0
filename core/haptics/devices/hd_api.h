#pragma once
// The part of OpenHaptics' HDAPI (3D Systems) the Phantom/Touch backend calls.
// With the SDK (SULCUS_HAVE_OPENHAPTICS) this is its own <HD/hd.h>; without it,
// the same functions and types are declared here from the public API reference
// so that the backend compiles and is tested against a test double in CI. The
// constants below are this file's own numbering: with the SDK, the SDK's apply.

#if defined(SULCUS_HAVE_OPENHAPTICS)
#include <HD/hd.h>
#else
extern "C" {
typedef unsigned int HHD;
typedef unsigned int HDenum;
typedef int HDint;
typedef unsigned short HDushort;
typedef double HDdouble;
typedef unsigned char HDboolean;
typedef const char* HDstring;
typedef unsigned int HDErrorCode;
typedef unsigned long HDSchedulerHandle;
typedef unsigned int HDCallbackCode;
typedef struct {
  HDErrorCode errorCode;
  int internalErrorCode;
  HHD hHD;
} HDErrorInfo;
#define HDCALLBACK
typedef HDCallbackCode(HDCALLBACK* HDSchedulerCallback)(void* pUserData);

#define HD_DEFAULT_DEVICE nullptr
#define HD_INVALID_HANDLE 0xFFFFFFFFu
#define HD_CALLBACK_DONE 0u
#define HD_CALLBACK_CONTINUE 1u
#define HD_DEFAULT_SCHEDULER_PRIORITY 0x7FFF
#define HD_MAX_SCHEDULER_PRIORITY 0xFFFF

// Capabilities and parameters.
#define HD_FORCE_OUTPUT 0x4000u
#define HD_CURRENT_BUTTONS 0x2000u
#define HD_CURRENT_TRANSFORM 0x2052u
#define HD_CURRENT_FORCE 0x2700u
#define HD_CURRENT_TORQUE 0x2703u
#define HD_NOMINAL_MAX_FORCE 0x2603u
#define HD_INPUT_DOF 0x2001u
#define HD_OUTPUT_DOF 0x2002u
#define HD_DEVICE_MODEL_TYPE 0x2501u

// Error codes.
#define HD_SUCCESS 0x0000u
#define HD_INVALID_ENUM 0x0100u
#define HD_DEVICE_FAULT 0x0300u
#define HD_COMM_ERROR 0x0302u
#define HD_TIMER_ERROR 0x0304u
#define HD_EXCEEDED_MAX_FORCE 0x0500u
#define HD_EXCEEDED_MAX_FORCE_IMPULSE 0x0501u
#define HD_EXCEEDED_MAX_VELOCITY 0x0502u
#define HD_FORCE_ERROR 0x0503u
#define HD_WARM_MOTORS 0x0504u
#define HD_COMM_CONFIG_ERROR 0x0700u

HHD hdInitDevice(HDstring pConfigName);
void hdDisableDevice(HHD hHD);
HDErrorInfo hdGetError(void);
HDstring hdGetErrorString(HDErrorCode errorCode);
void hdEnable(HDenum cap);
void hdStartScheduler(void);
void hdStopScheduler(void);
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback pCallback, void* pUserData,
                                         HDushort nPriority);
void hdUnschedule(HDSchedulerHandle hHandle);
void hdBeginFrame(HHD hHD);
void hdEndFrame(HHD hHD);
void hdGetDoublev(HDenum pname, HDdouble* params);
void hdGetIntegerv(HDenum pname, HDint* params);
void hdSetDoublev(HDenum pname, const HDdouble* params);
HDstring hdGetString(HDenum pname);
}
#endif
