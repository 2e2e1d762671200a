// Inside a container or chroot (scripts/toolchain.sh) only some host folders
// are the user's: a path elsewhere would silently read or write the root's
// own files. SOFTFLOW_SHARED_DIRS (colon-separated folders, set by
// scripts/toolchain.sh) names them; when it is set, every path the run reads
// or writes must lie under one of them. Unset (a plain machine): no check.
#pragma once
#include <string>

namespace softflow {

// Throws InputError naming `what` and `path` when SOFTFLOW_SHARED_DIRS is set
// and `path` (relative to the current folder, or absolute; symbolic links
// followed) lies outside every folder it lists.
void check_shared_path(const std::string& what, const std::string& path);

}  // namespace softflow
