#include "csv_series.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace softflow {

namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}
}  // namespace

CsvSeries::CsvSeries(bool root, const std::string& path, const std::string& header, long keep_up_to_step)
    : root_(root), path_(path) {
  if (!root_) return;
  std::string text = header + "\n";
  if (keep_up_to_step >= 0) {
    std::ifstream in(path);
    std::string line;
    if (in && std::getline(in, line)) {
      while (std::getline(in, line))
        if (!line.empty() && line[0] != '#' && std::atol(line.c_str()) <= keep_up_to_step)
          text += line + "\n";
    }
  }
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f) throw std::runtime_error("cannot write '" + tmp + "'");
  }
  std::filesystem::rename(tmp, path);
  file_.open(path, std::ios::app);
  if (!file_) throw std::runtime_error("cannot append to '" + path + "'");
}

void CsvSeries::append(const std::string& row) {
  if (root_) file_ << row << "\n" << std::flush;
}

std::map<std::string, std::vector<double>> read_columns(const std::string& path) {
  std::map<std::string, std::vector<double>> cols;
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (names.empty()) {
      names = split(line);
      for (const auto& n : names) cols[n];
      continue;
    }
    const auto cells = split(line);
    for (size_t c = 0; c < names.size(); ++c) {
      double v = NAN;
      if (c < cells.size() && !cells[c].empty()) v = std::strtod(cells[c].c_str(), nullptr);
      cols[names[c]].push_back(v);
    }
  }
  return cols;
}

}  // namespace softflow
