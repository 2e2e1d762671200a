// A CSV time series in the output folder, written by rank 0: the header (and,
// after a restart, the rows up to the checkpoint's step) replace the file
// whole, then rows are appended and flushed one by one, so an interruption
// loses at most the row being written. read_columns() gives the table back
// for the end-of-run averages.
#pragma once
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace softflow {

class CsvSeries {
 public:
  CsvSeries() = default;
  // root: whether this rank writes; keep_up_to_step >= 0 keeps the rows of an
  // existing file whose first column (the step) is <= it
  CsvSeries(bool root, const std::string& path, const std::string& header, long keep_up_to_step);
  void append(const std::string& row);  // one line, without the newline
  const std::string& path() const { return path_; }

 private:
  bool root_ = false;
  std::string path_;
  std::ofstream file_;
};

// The numeric columns of a CSV file with one header line (lines starting with
// '#' skipped; empty fields read as NaN). Missing file: empty map.
std::map<std::string, std::vector<double>> read_columns(const std::string& path);

}  // namespace softflow
