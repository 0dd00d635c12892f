#include "frontend/other_targets.h"

#include <algorithm>
#include <array>

namespace rcxc::frontend {
namespace {

// The names `nqc -Tscout`, `-Tcm`, `-Tspy` and `-TSwan` declare and neither
// `-Trcx` nor `-TRCX2` does (the RCX 2 names are is_rcx2_api_name's, in sema.cpp),
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

// The Swan's (`-TSwan`, a replacement firmware for the RCX brick): its system
// slots, motor powers, outputs D to F, message parameters and the like. None
// is also a Scout, CyberMaster or Spybot name.
constexpr auto kSwan = std::to_array<std::string_view>({
  "BitClear", "BitSet", "CLR_BREAKPOINTS", "CLR_DATALOG", "CLR_EVENTS", "CLR_INPUTS", "CLR_TASK_STACK", "CLR_TIMERS",
  "CLR_VARIABLES", "ClearAll", "CommErrorsFraming", "CommErrorsOverrun", "CommErrorsParity", "CommErrorsTimeout",
  "CurrentTask", "DISPLAY_EXCEPTION", "DatalogSize", "DebugTaskMode", "DefaultSerialComm", "DefaultSerialPacket",
  "DefaultStackSize", "EST_COUNTER_1", "EST_COUNTER_2", "EST_COUNTER_3", "EST_INFRARED_STATUS", "EST_LAST_IR_MSG",
  "EST_SENSOR_1", "EST_SENSOR_2", "EST_SENSOR_3", "EST_SENSOR_UNUSED", "EST_TIMER_1", "EST_TIMER_2", "EST_TIMER_3",
  "EST_TIMER_4", "EST_USER_EVENT_0", "EST_USER_EVENT_1", "EST_USER_EVENT_2", "EST_USER_EVENT_3", "EST_USER_EVENT_4",
  "EST_VIRTUAL_MOTOR", "EST_VIRTUAL_SENSOR", "EST_WAIT_FOR_MSG", "ES_ABOVE_UPPER", "ES_BELOW_LOWER", "ES_BETWEEN",
  "ES_UNDETERMINED", "EVENT_TYPE_4", "EVENT_TYPE_5", "EVENT_TYPE_6", "EVENT_TYPE_INFRARED_IDLE", "EVENT_TYPE_RESET",
  "EVENT_TYPE_VIRTUAL_MOTOR_CHANGE", "EVENT_TYPE_VIRTUAL_MOTOR_POWER", "EVENT_TYPE_VIRTUAL_SENSOR_DEF", "EventCounts",
  "EventSrc", "EventType", "ExpandedRemoteMessages", "ExpandedSubroutines", "FMT_HHMM", "FMT_MMSS", "FMT_MSSTENTHS",
  "FloatDuringInactivePWM", "GlobalVar", "IRM_ACCEPT_ALL", "IRM_ACCEPT_USER", "IRM_DISCARD", "IgnoreMessagesCPU",
  "ImmediateBatteryLevel", "InterCharTimeout", "IntrinsicIndGlobal", "LCDRefreshRate", "MAX_VOLUME", "MPD_FLOAT",
  "MPD_FWD", "MPD_OFF", "MPD_REV", "MSTimer", "MS_BRAKE", "MS_FLOAT", "MS_FWD", "MS_REV", "MTR_A", "MTR_B",
  "MTR_BRAKE_POWER_1", "MTR_BRAKE_POWER_2", "MTR_BRAKE_POWER_3", "MTR_BRAKE_POWER_4", "MTR_BRAKE_POWER_5",
  "MTR_BRAKE_POWER_6", "MTR_BRAKE_POWER_7", "MTR_BRAKE_POWER_8", "MTR_C", "MTR_D", "MTR_E", "MTR_F",
  "MTR_FLOAT_POWER_1", "MTR_FLOAT_POWER_2", "MTR_FLOAT_POWER_3", "MTR_FLOAT_POWER_4", "MTR_FLOAT_POWER_5",
  "MTR_FLOAT_POWER_6", "MTR_FLOAT_POWER_7", "MTR_FLOAT_POWER_8", "MTR_FWD_POWER_1", "MTR_FWD_POWER_2",
  "MTR_FWD_POWER_3", "MTR_FWD_POWER_4", "MTR_FWD_POWER_5", "MTR_FWD_POWER_6", "MTR_FWD_POWER_7", "MTR_FWD_POWER_8",
  "MTR_REV_POWER_1", "MTR_REV_POWER_2", "MTR_REV_POWER_3", "MTR_REV_POWER_4", "MTR_REV_POWER_5", "MTR_REV_POWER_6",
  "MTR_REV_POWER_7", "MTR_REV_POWER_8", "MemoryMapAddress", "MessageParam", "MissedSensorADConversions",
  "MotorBrakePower", "MotorPower128", "MotorPower8", "MotorPowerSigned", "MotorTransitionDelay", "Negate",
  "NoPowerDownOnAC", "OUT_D", "OUT_E", "OUT_F", "OpcodesPerTimeslice", "PlaySounds", "PowerDownDelay",
  "QueuedSoundCount", "ResetMSTimer", "RotDebouncedGlitches", "RotErrorsCount", "SENSOR_TYPE_ACTIVE_RAW",
  "SERIAL_COMM_9600", "SLS_RECEIVING_MSG", "SLS_TRANSMITTING", "SLS_UNKNOWN", "SLS_WAIT_FOR_MSG", "SMOTOR_FWD",
  "SOUND_EXCEPTION", "SOUND_SHORT_BLIP", "SYS_BATTERY_LEVEL", "SYS_COMM_ERRORS_FRAMING", "SYS_COMM_ERRORS_OVERRUN",
  "SYS_COMM_ERRORS_PARITY", "SYS_COMM_ERRORS_TIMEOUT", "SYS_CURRENT_TASK", "SYS_DATALOG_SIZE", "SYS_DEBUG_TASK_MODE",
  "SYS_DEFAULT_TASK_STACK_SIZE", "SYS_EXPANDED_RC_MESSAGES", "SYS_EXPANDED_SUBROUTINES",
  "SYS_FLOAT_DURING_INACTIVE_PWM", "SYS_IGNORE_MESSAGES_CPU", "SYS_INTER_CHAR_TIMEOUT", "SYS_LCD_REFRESH_RATE",
  "SYS_MEMORY_MAP_ADDRESS", "SYS_MOTOR_TRANSITION_DELAY", "SYS_NO_POWER_DOWN_ON_AC", "SYS_OPCODES_PER_TIMESLICE",
  "SYS_PLAY_SOUNDS", "SYS_POWER_DOWN_DELAY", "SYS_PREAMBLE_SIZE", "SYS_QUEUED_SOUND_COUNT",
  "SYS_ROT_DEBOUNCED_GLITCHES", "SYS_ROT_ERRORS_COUNT", "SYS_SENSOR_DELAY_CYCLES", "SYS_SENSOR_MISSED_CONVERSIONS",
  "SYS_SENSOR_REFRESH_RATE", "SYS_SENSOR_REFRESH_STATE", "SYS_SENSOR_SCAN_COUNT", "SYS_SENSOR_STARTUP_DELAY",
  "SYS_SERIAL_LINK_STATUS", "SYS_SOUND_PLAYING", "SYS_TASK_ACQUIRE_PRIORITY", "SYS_TASK_SCHEDULING_PRIORITY",
  "SYS_TRANSMITTER_RANGE", "SYS_UNSOLICITED_MESSAGES", "SYS_VOLUME", "SYS_WATCH_FORMAT", "SendMessageWithParam",
  "SensorDelayCycles", "SensorRefreshRate", "SensorRefreshState", "SensorScanCount", "SensorStartupDelay",
  "SerialLinkStatus", "SetDefaultSerialComm", "SetDefaultSerialPacket", "SetDefaultStackSize", "SetEventCounts",
  "SetEventSrc", "SetEventType", "SetExpandedRemoteMessages", "SetExpandedSubroutines", "SetFloatDuringInactivePWM",
  "SetInterCharTimeout", "SetLCDRefreshRate", "SetMessageByteParam", "SetMessageVariableParam", "SetMessageWordParam",
  "SetMotorBrakePower", "SetMotorPower128", "SetMotorPower8", "SetMotorPowerSigned", "SetMotorTransitionDelay",
  "SetNoPowerDownOnAC", "SetOpcodesPerTimeslice", "SetPlaySounds", "SetSensorRefreshRate", "SetSensorStartupDelay",
  "SetSystem", "SetSystemPreambleSize", "SetTaskAcquirePriority", "SetTaskSchedulingPriority", "SetVolume",
  "SetWatchFormat", "SoundActive", "StackAddress", "StackSize", "System", "SystemPreambleSize", "TaskAcquirePriority",
  "TaskSchedulingPriority", "TransmitterRange", "UnsolicitedMessages", "Volume", "WaitMS", "WatchFormat",
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
  if (holds(kSwan, name)) return "Swan firmware";
  return std::nullopt;
}

bool other_target_lists_are_sorted() {
  auto sorted = [](const auto& names) { return std::is_sorted(names.begin(), names.end()); };
  return sorted(kScout) && sorted(kCyberMaster) && sorted(kSpybot) && sorted(kScoutAndSpybot) && sorted(kSwan);
}

}  // namespace rcxc::frontend
