#include "frontend/other_targets.h"

#include <algorithm>
#include <array>

namespace rcxc::frontend {
namespace {

// The names `nqc -Tscout`, `-Tcm` and `-Tspy` declare and neither `-Trcx`
// nor `-TRCX2` does (the RCX 2 names are is_rcx2_api_name's, in sema.cpp),
// each list sorted for a binary search. Functions and constants alike.
constexpr auto kScout = std::to_array<std::string_view>({
  "CalibrateSensor", "CounterLimit", "EVENT_1_PRESSED", "EVENT_1_RELEASED", "EVENT_2_PRESSED",
  "EVENT_2_RELEASED", "EVENT_COUNTER_0", "EVENT_COUNTER_1", "EVENT_LIGHT_CLICK", "EVENT_LIGHT_DOUBLECLICK",
  "EVENT_LIGHT_HIGH", "EVENT_LIGHT_LOW", "EVENT_LIGHT_NORMAL", "EVENT_MESSAGE", "EVENT_TIMER_0", "EVENT_TIMER_1",
  "EVENT_TIMER_2", "EventFeedback", "SCOUT_MODE_POWER", "SCOUT_MODE_STANDALONE", "ScoutRules", "SelectSounds",
  "SetCounterLimit", "SetEventFeedback", "SetScoutMode", "SetScoutRules", "SetSensorClickTime",
  "SetSensorHysteresis", "SetSensorLowerLimit", "SetSensorUpperLimit", "SetTimerLimit", "TimerLimit",
});

constexpr auto kCyberMaster = std::to_array<std::string_view>({
  "AGC", "ClearTachoCounter", "DIRSPEED", "Drive", "ExternalMotorRunning", "OUT_L", "OUT_R", "OUT_X", "OnWait",
  "OnWaitDifferent", "SENSOR_L", "SENSOR_M", "SENSOR_R", "TachoCount", "TachoSpeed",
});

constexpr auto kSpybot = std::to_array<std::string_view>({
  "ACQUIRE_LED", "ANIMATION", "ANIMATION_ALARM", "ANIMATION_FLASH", "ANIMATION_GREEN_TO_RED",
  "ANIMATION_POINT_FORWARD", "ANIMATION_RED_TO_GREEN", "ANIMATION_SCAN", "ANIMATION_SPARKLE",
  "ANIMATION_THINKING", "ASPECT_BACK", "ASPECT_BACK_LEFT", "ASPECT_BACK_RIGHT", "ASPECT_FRONT",
  "ASPECT_FRONT_LEFT", "ASPECT_FRONT_RIGHT", "Action", "AnimateLED", "BATTERY_LOW", "BATTERY_MAX", "BATTERY_MIN",
  "BasicMove", "BeaconControl", "COMMAND_CONTROLLER", "CONTROLLER_BUTTON1", "CONTROLLER_BUTTON2",
  "CONTROLLER_BUTTON3", "CONTROLLER_BUTTON4", "CONTROLLER_BUTTON5", "ClearWorld", "CurrentTaskID",
  "DIRECTION_CENTER", "DIRECTION_LEFT", "DIRECTION_LEFT_OF_CENTER", "DIRECTION_RIGHT",
  "DIRECTION_RIGHT_OF_CENTER", "Disp", "EEPROM", "EEPROM_BIRTHDATE", "EEPROM_BOTDATA", "EEPROM_DEFAULTPINGRATE",
  "EEPROM_FIRSTTOKEN", "EEPROM_HIGHSCORE", "EEPROM_LASTTOKEN", "EEPROM_LONGID", "EEPROM_LOSSES",
  "EEPROM_MAXBOTS", "EEPROM_MAXTOKENS", "EEPROM_MISSIONID", "EEPROM_MISSIONPOINTS", "EEPROM_MISSIONSPLAYED",
  "EEPROM_MOTORCONTROL", "EEPROM_PLAYSECONDS", "EEPROM_POINTS", "EEPROM_ROBOTNAME", "EEPROM_RUNS",
  "EEPROM_SPECIES", "EEPROM_STATUS", "EEPROM_TOTALPLAYTIME", "EEPROM_USERLEVEL", "EEPROM_WINS",
  "EVENT_TYPE_ENTRY_CHANGED", "EVENT_TYPE_ENTRY_FOUND", "EVENT_TYPE_MSG_DISCARD", "EVENT_TYPE_MSG_RECEIVED",
  "EVENT_TYPE_VLL_MSG_RECEIVED", "EffectSound", "EffectTime", "FancyMove", "FindWorld", "FixedTone",
  "FixedWaitEffect", "Gate", "GateOff", "GetWorld", "GetWorldAspect", "GetWorldDirection", "GetWorldLinkID",
  "GetWorldNote", "GetWorldRange", "GetWorldShortID", "Glide", "INDEX_BROADCAST", "INDEX_INVALID",
  "INDEX_LINKCAST", "LED", "LED_ALL", "LED_ALL_GREEN", "LED_ALL_RED", "LED_ALL_RED_GREEN", "LED_GREEN1",
  "LED_GREEN2", "LED_GREEN3", "LED_MODE_BLINK", "LED_MODE_DURATION", "LED_MODE_GREEN_SCALE",
  "LED_MODE_GREEN_SCALE_BLINK", "LED_MODE_ON", "LED_MODE_RED_SCALE", "LED_MODE_RED_SCALE_BLINK",
  "LED_MODE_SCALE", "LED_MODE_SCALE_BLINK", "LED_MODE_SCALE_DURATION", "LED_MODE_VLL", "LED_MODE_VLL_BLINK",
  "LED_MODE_VLL_DURATION", "LED_MODE_YELLOW", "LED_MODE_YELLOW_BLINK", "LED_MODE_YELLOW_DURATION", "LED_RED1",
  "LED_RED2", "LED_RED3", "LED_YELLOW", "LinkID", "MOTORCONTROL_LEFTDIR", "MOTORCONTROL_NORMALSPEEDMASK",
  "MOTORCONTROL_RIGHTDIR", "MOTORCONTROL_SLOWSPEEDMASK", "MOVE_BASIC", "MOVE_BASIC_AVOID_LEFT",
  "MOVE_BASIC_AVOID_RIGHT", "MOVE_BASIC_BACKWARD", "MOVE_BASIC_FORWARD", "MOVE_BASIC_REST",
  "MOVE_BASIC_SPIN_LEFT", "MOVE_BASIC_SPIN_RIGHT", "MOVE_BASIC_STOP", "MOVE_BASIC_TURN_LEFT",
  "MOVE_BASIC_TURN_RIGHT", "MOVE_FANCY", "MOVE_FANCY_BUG_FORWARD", "MOVE_FANCY_DANCE", "MOVE_FANCY_FAKE_LEFT",
  "MOVE_FANCY_LAZY", "MOVE_FANCY_RAKE_RIGHT", "MOVE_FANCY_SCAN", "MOVE_FANCY_SEARCH", "MOVE_FANCY_SHAKE",
  "MOVE_FANCY_STEP", "MOVE_FANCY_STEP_BACK", "MOVE_FANCY_WALK", "MOVE_FANCY_WALK_BACK", "MOVE_FANCY_ZIGZAG",
  "MOVE_MASK", "MOVE_RANDOM", "MOVE_RANDOM_BACKWARD", "MOVE_RANDOM_FORWARD", "MOVE_RANDOM_REST",
  "MOVE_RANDOM_SPIN_LEFT", "MOVE_RANDOM_SPIN_RIGHT", "MOVE_RANDOM_TURN_LEFT", "MOVE_RANDOM_TURN_RIGHT",
  "MOVE_SLOWDOWN", "MOVE_SLOWDOWN_BACKWARD", "MOVE_SLOWDOWN_FORWARD", "MOVE_SLOWDOWN_SPIN_LEFT",
  "MOVE_SLOWDOWN_SPIN_RIGHT", "MOVE_SPEEDUP", "MOVE_SPEEDUP_BACKWARD", "MOVE_SPEEDUP_FORWARD",
  "MOVE_SPEEDUP_SPIN_LEFT", "MOVE_SPEEDUP_SPIN_RIGHT", "MOVE_TYPE_MASK", "MSG_COMMAND", "MSG_HI_BYTE",
  "MSG_INDEX", "MSG_IR", "MSG_LO_BYTE", "MSG_NONE", "MSG_PC", "PingControl", "PingData", "PingID",
  "PingInterval", "Pop", "Push", "RANGE_ANYWHERE", "RANGE_HERE", "RANGE_NOWHERE", "RANGE_THERE", "RCRxChannel",
  "RCTXMODE_CONTINUOUS", "RCTXMODE_SINGLE_SHOT", "RCTxChannel", "RCTxMode", "RC_CHANNEL_BROADCAST",
  "RC_CHANNEL_DISABLED", "REL_EQ", "REL_GT", "REL_LT", "REL_NE", "RandomMove", "RepeatAnimation", "RepeatEffect",
  "RxMessage", "RxMessageChannel", "RxMessageID", "RxMessageIndex", "RxMessageLock", "SERIAL_BAUD",
  "SERIAL_BAUD_2400", "SERIAL_BAUD_4800", "SERIAL_BAUD_9600", "SERIAL_BIPHASE", "SERIAL_BIPHASE_OFF",
  "SERIAL_BIPHASE_ON", "SERIAL_CHANNEL", "SERIAL_CHANNEL_IR", "SERIAL_CHANNEL_PC", "SERIAL_CHECKSUM",
  "SERIAL_CHECKSUM_NONE", "SERIAL_CHECKSUM_SUM", "SERIAL_CHECKSUM_ZERO_SUM", "SERIAL_PREAMBLE_LEN",
  "SERIAL_PREAMBLE_POS", "SERIAL_TYPE", "SERIAL_TYPE_RC", "SERIAL_TYPE_RCX", "SERIAL_TYPE_SPYBOT",
  "SERIAL_TYPE_USER", "SOUNDEFFECT", "SOUND_ACTIVATE_CLOAK", "SOUND_ACTIVATE_FLASH_BLIND",
  "SOUND_ACTIVATE_REFLECT", "SOUND_ACTIVATE_SHIELDS", "SOUND_BIG_EXPLOSION", "SOUND_BOMB_ALERT", "SOUND_BOOST",
  "SOUND_BURNT", "SOUND_CRASH", "SOUND_DANGER_ALERT", "SOUND_DEACTIVATE_CLOAK", "SOUND_DEACTIVATE_REFLECT",
  "SOUND_DEACTIVATE_SHIELDS", "SOUND_DIZZY", "SOUND_EXPLOSION", "SOUND_FIGHT", "SOUND_FINAL_COUNTDOWN",
  "SOUND_FIRE_ELECTRONET", "SOUND_FIRE_LASER", "SOUND_FIRE_SPINNER", "SOUND_FREEZE", "SOUND_GEIGER",
  "SOUND_GENERAL_ALERT", "SOUND_GOTO", "SOUND_GOT_IT", "SOUND_GRINDED", "SOUND_HELP", "SOUND_HIT_BY_ELECTRONET",
  "SOUND_HIT_BY_LASER", "SOUND_HIT_BY_SPINNER", "SOUND_HIT_BY_WIND", "SOUND_IM_IT", "SOUND_LOW_ENERGY_ALERT",
  "SOUND_MAGNET", "SOUND_NONE", "SOUND_OUCH", "SOUND_OUT_OF_ENERGY_ALERT", "SOUND_PLACE_BOMB", "SOUND_POINT_TO",
  "SOUND_PROXIMITY_ALERT", "SOUND_QUAD_DAMAGE", "SOUND_REFLECT", "SOUND_REPULSE", "SOUND_REVERSE", "SOUND_SCAN",
  "SOUND_SCORE_ALERT", "SOUND_SHOCKED", "SOUND_SIREN", "SOUND_SLOW", "SOUND_SMACKED", "SOUND_TAG",
  "SOUND_TICK_TOCK", "SOUND_TIME_ALERT", "SOUND_TRILL_DOWN", "SOUND_TRILL_UP", "SOUND_TURBO", "SOUND_WHISPER",
  "SOUND_WHISTLE", "SOUND_YELL", "SPECIES_GIGAMESH", "SPECIES_SHADOWSTRIKE", "SPECIES_SNAPTRAX",
  "SPECIES_TECHNOJAW", "SPY_ASPECT", "SPY_DIRECTION", "SPY_INFO", "SPY_LINKID", "SPY_NOTE", "SPY_RANGE",
  "SPY_SHORTID", "SPY_TARGETID", "STATUS_DOWNLOADING", "STATUS_INITIALIZING", "STATUS_LOCKED",
  "SendAllRangeMessage", "SendRCXMessage", "SerialBaud", "SerialBiPhase", "SerialChannel", "SerialChecksum",
  "SerialPreambleLen", "SerialPreamblePos", "SerialType", "SetAnimation", "SetEEPROM", "SetEffectSound",
  "SetEffectTime", "SetLED", "SetLinkID", "SetPingData", "SetPingInterval", "SetRCRxChannel", "SetRCTxChannel",
  "SetRCTxMode", "SetRxMessageLock", "SetSerialBaud", "SetSerialBiPhase", "SetSerialChannel",
  "SetSerialChecksum", "SetSerialPreambleLen", "SetSerialPreamblePos", "SetSerialType", "SetStack",
  "SetTargetID", "SetTargetNote", "SetTimerState", "SetWorldNote", "SlowDownMove", "SpeedUpMove", "Stack",
  "StartTask", "StopTask", "Sum2Mem", "Sum4Mem", "TARGET_NONE", "TIMER_RUNNING", "TIMER_STOPPED", "Target",
  "TimerState", "Tone", "VLL", "Vibrato", "WaitEffect", "World", "WorldAspect", "WorldDirection", "WorldLinkID",
  "WorldNote", "WorldRange", "WorldShortID",
});

// Both the Scout's and the Spybot's (their light and VLL).
constexpr auto kScoutAndSpybot = std::to_array<std::string_view>({
  "LIGHT_OFF", "LIGHT_ON", "SendVLL", "SetLight",
});

template <std::size_t N>
bool holds(const std::array<std::string_view, N>& names, std::string_view name) {
  return std::binary_search(names.begin(), names.end(), name);
}

}  // namespace

std::optional<std::string_view> other_target_of(std::string_view name) {
  if (holds(kScout, name)) return "Scout";
  if (holds(kCyberMaster, name)) return "CyberMaster";
  if (holds(kSpybot, name)) return "Spybot";
  if (holds(kScoutAndSpybot, name)) return "Scout and Spybot";
  return std::nullopt;
}

bool other_target_lists_are_sorted() {
  auto sorted = [](const auto& names) { return std::is_sorted(names.begin(), names.end()); };
  return sorted(kScout) && sorted(kCyberMaster) && sorted(kSpybot) && sorted(kScoutAndSpybot);
}

}  // namespace rcxc::frontend
