// The code's version, "<project version>+<git describe>" at configure time.
// Kept in one generated source file (version.cpp.in) so that a new commit
// recompiles that file only.
#pragma once

namespace softflow {
const char* version();
}
