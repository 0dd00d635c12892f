// Several bricks in one room. A program's Send message goes out by
// infrared to every other brick (the seed: "broadcasting a set message
// request over the infrared link"), so an IR master and its slaves can be
// run together without robots: `rcxc run master.nqc slave.nqc`.
//
// The machines go forward side by side in virtual time. A message is on
// the air for the time its packet takes and reaches the others when the
// packet ends; two bricks' packets on the air at once garble each other and
// neither arrives; a brick that switches off sends nothing more. docs/emulator.md ("Several bricks") says what is measured
// and what is our choice.
#pragma once

#include <span>
#include <vector>

#include "runtime/vm.h"

namespace rcx {

// A Set message packet is 9 bytes (55 ff 00; f7 and the value, each
// followed by its complement; the checksum and its complement) at 2400
// baud, 11 bits a byte (start, 8 data, odd parity, stop): 41.25 ms.
inline constexpr int kMessagePacketBytes = 9;
inline constexpr Micros kMessageAirUs = Micros{kMessagePacketBytes} * 11 * 1'000'000 / 2400;

struct Transmission {
  int from = 0;                  // the sending brick, an index into the room
  int value = 0;                 // 0..255
  Micros sent_us = 0;            // when the program's Send message ran
  Micros start_us = 0;           // on the air from (after the brick's previous packet, if one was still going out)
  Micros end_us = 0;             // and until: the others have it then
  bool collided = false;         // another brick's packet was on the air too: nobody got this one
  std::vector<int> received_by;  // the bricks whose programs were still running when it arrived
  bool unfinished = false;       // the run ended before the packet did (it may not have started): nobody got it
  bool switched_off = false;     // the brick switched off first: end_us is then, the packet never whole
};

// Runs the machines (programs loaded and started) together until every one
// has stopped or `limit_us`, then closes each run as Machine::run(limit_us)
// does. Returns every packet sent, in the order they went on the air.
std::vector<Transmission> run_room(std::span<Machine* const> machines, Micros limit_us);

}  // namespace rcx
