#include "shared_paths.hpp"

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "config.hpp"

namespace fs = std::filesystem;

namespace softflow {

namespace {
bool is_under(const fs::path& p, const fs::path& dir) {
  auto d = dir.begin(), q = p.begin();
  for (; d != dir.end(); ++d, ++q) {
    if (d->empty()) continue;  // the empty last element of a trailing '/'
    if (q == p.end() || *q != *d) return false;
  }
  return true;
}
}  // namespace

void check_shared_path(const std::string& what, const std::string& path) {
  const char* env = std::getenv("SOFTFLOW_SHARED_DIRS");
  if (!env || !*env || path.empty()) return;
  // symbolic links followed, where they resolve to paths (/dev/fd/N of a
  // pipe does not: taken as written)
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
  if (ec) p = fs::absolute(path).lexically_normal();
  std::stringstream list(env);
  std::string dir, names;
  while (std::getline(list, dir, ':')) {
    if (dir.empty()) continue;
    if (is_under(p, fs::path(dir).lexically_normal())) return;
    names += (names.empty() ? "" : ", ") + dir;
  }
  throw InputError(what + " '" + path + "' (" + p.string() +
                   ") is outside the folders shared with the toolchain root (" + names +
                   "): it would be the root's own, not this machine's; use a path under one of them");
}

}  // namespace softflow
