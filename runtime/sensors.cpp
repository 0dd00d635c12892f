#include "runtime/sensors.h"

#include <cstdint>

namespace rcx {
namespace {

constexpr int kOutOfRange = 0x7fff;

// Piecewise-linear temperature curve of the original firmware (RCX Internals
// listing): tenths of °C = (raw * scale + offset) / 100 for raw below `upto`.
struct TempSegment {
  int upto, scale, offset;
};
constexpr TempSegment kTemperature[] = {
    {340, -261, 145200}, {390, -194, 123000}, {478, -144, 103500}, {520, -123, 93600},
    {790, -107, 85200},  {886, -134, 106600}, {929, -175, 142600},
};
constexpr int kTemperatureLowestRaw = 290;

}  // namespace

SensorMode default_mode(SensorType type) {
  switch (type) {
    case SensorType::Raw: return SensorMode::Raw;
    case SensorType::Touch: return SensorMode::Boolean;
    case SensorType::Temperature: return SensorMode::Celsius;
    case SensorType::Light: return SensorMode::Percent;
    case SensorType::Rotation: return SensorMode::Angle;
  }
  return SensorMode::Raw;
}

void feed_raw(Sensor& s, int raw) {
  bool next = s.boolean;
  if (s.slope == 0) {
    if (raw > 562) next = false;       // high raw reads as 0
    else if (raw < 460) next = true;   // low raw reads as 1
  } else {
    int delta = raw - s.raw;
    if (delta > s.slope) next = false;
    else if (-delta > s.slope) next = true;
  }
  if (next != s.boolean) ++s.transitions;
  s.boolean = next;
  s.raw = raw;
}

int percent_of_raw(int raw) {
  // Firmware: below 0x187 reads 100, else (1023 - raw) * 25 / 156 (which gives 101 at raw 391).
  if (raw < 0x187) return 100;
  return (1023 - raw) * 25 / 156;
}

int celsius_tenths_of_raw(int raw) {
  if (raw < kTemperatureLowestRaw) return kOutOfRange;
  for (const auto& seg : kTemperature)
    if (raw < seg.upto) return (raw * seg.scale + seg.offset) / 100;
  return kOutOfRange;
}

int fahrenheit_tenths_of_raw(int raw) {
  int c = celsius_tenths_of_raw(raw);
  return c == kOutOfRange ? kOutOfRange : c * 18 / 10 + 320;
}

int sensor_reading(const Sensor& s) {
  switch (s.mode) {
    case SensorMode::Raw: return s.raw;
    case SensorMode::Boolean: return s.boolean ? 1 : 0;
    case SensorMode::EdgeCount: return static_cast<std::int16_t>(s.transitions);
    case SensorMode::PulseCount: return static_cast<std::int16_t>(s.transitions / 2);
    case SensorMode::Percent: return percent_of_raw(s.raw);
    case SensorMode::Celsius: return celsius_tenths_of_raw(s.raw);
    case SensorMode::Fahrenheit: return fahrenheit_tenths_of_raw(s.raw);
    case SensorMode::Angle: return static_cast<std::int16_t>(static_cast<std::uint16_t>(s.rotation - s.rotation_zero));
  }
  return 0;
}

}  // namespace rcx
