// A program that keeps the brick talking: it sets var 3 to 7, then sends
// message 42 every 1/100 s, for the tests that check a host's requests get
// through the brick's broadcasts (in memory and over a pty).
#pragma once

#include "rcx/image.h"

namespace rcx::test {

inline Image broadcasting_program() {
  Image image;
  image.fragments.push_back({FragmentType::Task, 0, {0x14, 0x03, 0x02, 0x07, 0x00,   // var 3 = 7
                                                     0xB2, 0x02, 42,                  // send message 42
                                                     0x43, 0x02, 1, 0x00,             // wait 1/100 s
                                                     0x27, 0x88}});                   // back to the send
  return image;
}

}  // namespace rcx::test
