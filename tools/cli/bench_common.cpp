// `frix bench`: the CSV columns, the problem families, small helpers.
#include "bench.hpp"

#include "bench_protocol.hpp"

#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdio>

namespace frix_cli {

std::vector<std::string> runs_header() {
    return {"problem", "family", "contacts", "dofs", "solver", "status", "iterations", "error",
            "time", "solver_id", "tolerance", "time_limit", "max_iter", "reported_error", "note",
            "peak_memory_mb", "stored_blocks", "error_scaled"};
}

std::string number_text(double v) { return std::isnan(v) ? "" : frix_bench::exact(v); }

std::vector<std::string> run_fields(const RunRecord &r) {
    const auto count = [](std::int64_t n) { return n < 0 ? std::string() : std::to_string(n); };
    return {r.problem, r.family, count(r.contacts), count(r.dofs), r.solver,
            r.status, std::to_string(r.iterations), number_text(r.error), number_text(r.time),
            std::to_string(r.solver_id), number_text(r.tolerance), number_text(r.time_limit),
            std::to_string(r.max_iter), number_text(r.reported_error), r.note, number_text(r.peak_memory_mb),
            number_text(r.stored_blocks), number_text(r.error_scaled)};
}

std::vector<std::string> traces_header() {
    return {"problem", "solver", "iteration", "elapsed", "error"};
}

namespace {

// File-name pattern -> family, after shared/fclib/MANIFEST.md and fclib-large. The first
// pattern found in the name wins (case matters: "spheres-in-a-box" is not "Spheres-n400").
const struct {
    const char *pattern, *family;
} kFamilies[] = {
    {"Capsules", "Capsules"},        {"Box_Stacks", "BoxesStack"},
    {"BoxesStack", "BoxesStack"},    {"local_problem_test", "BoxesStack"},
    {"PerioBox", "PR_PerioBox"},     {"spheres-in-a-box", "SpheresBox"},
    {"CubeH8", "Cubes_H8"},          {"Cubes_H8", "Cubes_H8"},
    {"LMGC_GFC3D", "Cubes_H8"},      {"OneObject", "OneObject"},
    {"Confeti", "Confeti"},          {"NESpheres", "NESpheres"},
    {"RockPile", "RockPile"},        {"Rover", "Rover"},
    {"TwoRods", "TwoRods"},          {"Kapla", "Kapla"},
    {"Spheres-", "Spheres"},         {"Chute", "Chute"},
    {"FC3D_Example", "toy"},         {"GFC3D_Example", "toy"},
    {"FrictionContact3D_", "toy"},
};

}  // namespace

std::string problem_family(const std::string &file_name) {
    for (const auto &f : kFamilies)
        if (file_name.find(f.pattern) != std::string::npos) return f.family;
    return "other";
}

std::string self_directory() {
    char buf[PATH_MAX];
    ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return ".";
    std::string path(buf, static_cast<std::size_t>(n));
    std::size_t slash = path.rfind('/');
    return slash == std::string::npos ? "." : path.substr(0, slash);
}

std::string clock_text(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) seconds = 0;
    long s = std::lround(seconds);
    char buf[32];
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
        std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
    return buf;
}

}  // namespace frix_cli
