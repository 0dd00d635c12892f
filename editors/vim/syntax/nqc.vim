" Vim syntax file
" Language: NQC (Not Quite C) for the LEGO RCX, as rcxc compiles it
" The API names are those of rcxc's stdlib/rcx.nqh (tests/lsp/editors_test.cpp
" checks that every one is listed here).
if exists("b:current_syntax")
  finish
endif

syn keyword nqcStatement  if else while do until for repeat switch case default break continue return goto
syn keyword nqcTaskControl start stop
syn keyword nqcStructure  task sub
syn keyword nqcType       void int const inline
syn keyword nqcBoolean    true false
syn keyword nqcAsm        asm
syn keyword nqcBuiltin    __source __source_arg
syn keyword nqcTodo       contained TODO FIXME XXX NOTE
syn keyword nqcApiFunction SetOutput SetDirection SetPower On Off Float Fwd Rev Toggle OnFwd OnRev Wait OnFor
  \ ClearTimer OutputStatus UploadDatalog SetWatch SetSensorType SetSensorMode SetSensor ClearSensor PlaySound PlayTone SelectDisplay
  \ ClearMessage SendMessage SetTxPower CreateDatalog AddToDatalog SetSleepTime SleepNow StopAllTasks _init Timer Watch
  \ SensorValue SensorType SensorMode SensorValueRaw SensorValueBool Message Random Program
syn keyword nqcApiConstant T1 T2 T3 T4 OUT_A OUT_B OUT_C OUT_AB OUT_AC OUT_BC OUT_ABC OUT_FLOAT OUT_OFF OUT_ON OUT_REV
  \ OUT_TOGGLE OUT_FWD OUT_LOW OUT_HALF OUT_FULL SENSOR_1 SENSOR_2 SENSOR_3 S1 S2 S3 SENSOR_TYPE_NONE
  \ SENSOR_TYPE_TOUCH SENSOR_TYPE_TEMPERATURE SENSOR_TYPE_LIGHT SENSOR_TYPE_ROTATION SENSOR_MODE_RAW
  \ SENSOR_MODE_BOOL SENSOR_MODE_EDGE SENSOR_MODE_PULSE SENSOR_MODE_PERCENT SENSOR_MODE_CELSIUS
  \ SENSOR_MODE_FAHRENHEIT SENSOR_MODE_ROTATION SENSOR_TOUCH SENSOR_LIGHT SENSOR_ROTATION SENSOR_CELSIUS
  \ SENSOR_FAHRENHEIT SENSOR_PULSE SENSOR_EDGE SOUND_CLICK SOUND_DOUBLE_BEEP SOUND_DOWN SOUND_UP SOUND_LOW_BEEP
  \ SOUND_FAST_UP DISPLAY_WATCH DISPLAY_SENSOR_1 DISPLAY_SENSOR_2 DISPLAY_SENSOR_3 DISPLAY_OUT_A DISPLAY_OUT_B
  \ DISPLAY_OUT_C TX_POWER_LO TX_POWER_HI _SENSOR_CFG

syn match   nqcNumber     "\<\d\+\>"
syn match   nqcNumber     "\<0[xX]\x\+\>"
syn region  nqcString     start=+"+ skip=+\\\\\|\\"+ end=+"+ oneline
syn match   nqcCharacter  "'\\\=.'"
syn region  nqcComment    start="/\*" end="\*/" contains=nqcTodo,@Spell
syn match   nqcComment    "//.*$" contains=nqcTodo,@Spell
syn match   nqcDirective  "^\s*#\s*\(define\|undef\|include\|if\|ifdef\|ifndef\|elif\|else\|endif\|error\|pragma\)\>"
syn region  nqcIncluded   start=+"+ end=+"+ contained
syn match   nqcInclude    "^\s*#\s*include\s*[<"].*" contains=nqcIncluded,nqcDirective
" The expectations `rcxc test` reads (docs/testing.md).
syn match   nqcTestDirective "//\s*@\(expect\|input\|for\|seed\|scenario\|options\|brick\|nqc-differs\)\S*" containedin=nqcComment contained

hi def link nqcStatement     Statement
hi def link nqcTaskControl   Statement
hi def link nqcStructure     Structure
hi def link nqcType          Type
hi def link nqcBoolean       Boolean
hi def link nqcAsm           Keyword
hi def link nqcBuiltin       Special
hi def link nqcApiFunction   Function
hi def link nqcApiConstant   Constant
hi def link nqcNumber        Number
hi def link nqcString        String
hi def link nqcCharacter     Character
hi def link nqcComment       Comment
hi def link nqcTodo          Todo
hi def link nqcDirective     PreProc
hi def link nqcInclude       Include
hi def link nqcIncluded      String
hi def link nqcTestDirective SpecialComment

let b:current_syntax = "nqc"
