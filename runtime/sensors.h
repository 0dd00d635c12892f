// How the firmware turns a sensor's raw readings into the value a program
// sees (seed: Set sensor mode / Set sensor type; numbers in docs/emulator.md).
#pragma once

#include "runtime/vm.h"

namespace rcx {

// The mode Set sensor type selects for each type.
SensorMode default_mode(SensorType type);
// Feeds one new raw reading (0..1023): updates the boolean state with the
// 460/562 hysteresis (slope 0) or the slope rule, counting transitions.
void feed_raw(Sensor& sensor, int raw);
// The value in the sensor's current mode.
int sensor_reading(const Sensor& sensor);
// Mode conversions of a raw value.
int percent_of_raw(int raw);
int celsius_tenths_of_raw(int raw);       // 0x7fff outside the sensor's range
int fahrenheit_tenths_of_raw(int raw);    // 0x7fff outside the sensor's range

}  // namespace rcx
