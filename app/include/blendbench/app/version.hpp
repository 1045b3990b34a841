#pragma once
// The program's version: the project version of CMakeLists.txt and, when built from a git
// checkout, the commit ("0.1.0 (commit 1a2b3c4d5e6f)", "+dirty" after it when the tracked files
// differed from that commit). `blendbench --version` prints it and every summary.json carries it
// as `version`.

namespace blendbench {

const char* version_string();

}  // namespace blendbench
