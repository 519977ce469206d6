#pragma once
// A small CSV table written atomically (mdbrief/internal/base/io/atomic_file.hpp), so an interrupted run
// never leaves a half-written result that the plot script would read.
#include <string>
#include <vector>

namespace mdbrief::eval {

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> header);

  // Starts a new row; cells are appended with add().
  CsvTable& row();
  CsvTable& add(const std::string& cell);
  CsvTable& add(double value);  // %.6g
  CsvTable& add(int value);

  // Creates path's folder if missing. Throws std::runtime_error naming the path if it cannot be
  // written.
  void write(const std::string& path) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace mdbrief::eval
