// Generated NQC programs for the stress tests and the frontend benchmark:
// valid programs whose size or depth is the point.
#pragma once

#include <string>

namespace rcxc::test {

// `depth` nested blocks, each an if / while / repeat around the next, with
// an expression nested as deep in the middle.
inline std::string deeply_nested_program(int depth) {
  std::string s = "int x;\ntask main()\n{\n";
  for (int i = 0; i < depth; ++i) {
    switch (i % 3) {
      case 0: s += "if (x < " + std::to_string(i) + ")\n{\n"; break;
      case 1: s += "while (x > " + std::to_string(i) + ")\n{\n"; break;
      default: s += "repeat (2)\n{\n"; break;
    }
  }
  s += "x = ";
  for (int i = 0; i < depth; ++i) s += "(x + ";
  s += "1";
  for (int i = 0; i < depth; ++i) s += ")";
  s += ";\n";
  for (int i = 0; i < depth; ++i) s += "}\n";
  s += "}\n";
  return s;
}

// A program of at least `lines` lines: one task made of many small
// statements using the stdlib, globals and locals, plus subs.
inline std::string long_program(int lines) {
  std::string s = "int a, b, c;\n#define STEP 3\nsub helper()\n{\n  a = a + 1;\n}\n";
  int written = 6;
  s += "task main()\n{\n  int i = 0;\n";
  written += 3;
  for (int n = 0; written < lines - 1; ++n) {
    switch (n % 8) {
      case 0: s += "  a = b * STEP + c / 2 - (i % 5);\n"; break;
      case 1: s += "  if (a > b) { b = a; } else { c++; }\n"; break;
      case 2: s += "  OnFwd(OUT_A + OUT_C);\n"; break;
      case 3: s += "  Wait(Random(10) + 1);\n"; break;
      case 4: s += "  while (i < 3) i++;\n"; break;
      case 5: s += "  helper();\n"; break;
      case 6: s += "  if (SENSOR_1 == 1) Off(OUT_A);\n"; break;
      default: s += "  i = Timer(0) > 100 ? 0 : i + 1;\n"; break;
    }
    ++written;
  }
  s += "}\n";
  return s;
}

}  // namespace rcxc::test
