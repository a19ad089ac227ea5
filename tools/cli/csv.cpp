#include "csv.hpp"

#include "cli.hpp"

#include <fstream>
#include <sstream>

namespace frix_cli {

std::string csv_field(const std::string &value) {
    if (value.find_first_of(",\"\r\n") == std::string::npos) return value;
    std::string out = "\"";
    for (char c : value) {
        if (c == '"') out += '"';
        out += c;
    }
    out += '"';
    return out;
}

std::string csv_row(const std::vector<std::string> &fields) {
    std::string out;
    for (std::size_t k = 0; k < fields.size(); ++k) {
        if (k) out += ',';
        out += csv_field(fields[k]);
    }
    out += '\n';
    return out;
}

std::vector<std::vector<std::string>> csv_parse(const std::string &text) {
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> row;
    std::string field;
    bool quoted = false, row_started = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (quoted) {
            if (c != '"') {
                field += c;
            } else if (i + 1 < text.size() && text[i + 1] == '"') {
                field += '"';
                ++i;
            } else {
                quoted = false;
            }
            continue;
        }
        row_started = true;
        if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            row.push_back(field);
            field.clear();
        } else if (c == '\n' || c == '\r') {
            if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
            row.push_back(field);
            rows.push_back(row);
            row.clear();
            field.clear();
            row_started = false;
        } else {
            field += c;
        }
    }
    if (row_started || !field.empty()) {
        row.push_back(field);
        rows.push_back(row);
    }
    return rows;
}

CsvTable CsvTable::read(const std::string &path, const std::vector<std::string> &required) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read " + path);
    std::ostringstream text;
    text << in.rdbuf();
    CsvTable t;
    auto rows = csv_parse(text.str());
    if (rows.empty()) fail(path + ": empty file, expected a header line");
    t.header_ = rows.front();
    t.rows_.assign(rows.begin() + 1, rows.end());
    for (const std::string &col : required)
        if (!t.has(col)) fail(path + ": no column '" + col + "'");
    return t;
}

int CsvTable::index(const std::string &column) const {
    for (std::size_t k = 0; k < header_.size(); ++k)
        if (header_[k] == column) return static_cast<int>(k);
    return -1;
}

const std::string &CsvTable::get(std::size_t row, const std::string &column) const {
    static const std::string empty;
    int k = index(column);
    if (k < 0 || row >= rows_.size() || static_cast<std::size_t>(k) >= rows_[row].size())
        return empty;
    return rows_[row][static_cast<std::size_t>(k)];
}

}  // namespace frix_cli
