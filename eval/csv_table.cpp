#include "csv_table.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "mdbrief/internal/base/io/atomic_file.hpp"

namespace mdbrief::eval {

CsvTable::CsvTable(std::vector<std::string> header) : header_(std::move(header)) {}

CsvTable& CsvTable::row() {
  rows_.emplace_back();
  return *this;
}

CsvTable& CsvTable::add(const std::string& cell) {
  if (rows_.empty()) rows_.emplace_back();
  rows_.back().push_back(cell);
  return *this;
}

CsvTable& CsvTable::add(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", value);
  return add(std::string(buf));
}

CsvTable& CsvTable::add(int value) { return add(std::to_string(value)); }

void CsvTable::write(const std::string& path) const {
  std::string text;
  auto line = [&text](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) text += (i ? "," : "") + cells[i];
    text += '\n';
  };
  line(header_);
  for (const auto& r : rows_) line(r);
  const std::filesystem::path target(path);
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  internal::writeFileAtomically(target, text);
}

}  // namespace mdbrief::eval
