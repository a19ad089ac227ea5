// CSV as RFC 4180 has it: fields with a comma, a quote or a line break are quoted, quotes
// doubled. The bench's files are read back by `frix bench --report` and by the plot script
// (Python's csv module), so problem names with commas or quotes must survive the trip.
#pragma once

#include <string>
#include <vector>

namespace frix_cli {

std::string csv_field(const std::string &value);
// A whole row, fields joined by commas and ended by "\n".
std::string csv_row(const std::vector<std::string> &fields);
// Every row of a CSV text (quoted fields may hold commas, quotes and line breaks). A
// trailing line break does not make an empty row; "\r\n" line ends are accepted.
std::vector<std::vector<std::string>> csv_parse(const std::string &text);

// A CSV file read into its header and rows, with fields looked up by column name.
class CsvTable {
public:
    // Fails (Failure) with a message naming the file when it cannot be read or lacks a
    // required column.
    static CsvTable read(const std::string &path, const std::vector<std::string> &required);
    std::size_t rows() const { return rows_.size(); }
    bool has(const std::string &column) const { return index(column) >= 0; }
    // The field, or "" when the column is absent or the row is short.
    const std::string &get(std::size_t row, const std::string &column) const;

private:
    int index(const std::string &column) const;
    std::vector<std::string> header_;
    std::vector<std::vector<std::string>> rows_;
};

}  // namespace frix_cli
