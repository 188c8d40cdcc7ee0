#pragma once
// The window's mouse and keyboard device is the core's key device
// (core/haptics/key_device.h), which the scripted "keys" student plays too.

#include "core/haptics/key_device.h"
