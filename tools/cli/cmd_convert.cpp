// `frix convert IN OUT.hdf5`: any problem frix reads (FCLIB, Siconos .dat) written as FCLIB.
// A global problem stays global (M, H, f, w): converting never reduces or solves.
#include "args.hpp"
#include "cli.hpp"

namespace frix_cli {

int cmd_convert(int argc, char **argv) {
    ArgCursor args("convert", argc, argv);
    std::string in, out, title;
    bool have_title = false, force = false;
    while (!args.done()) {
        if (args.flag("--help") || args.flag("-h")) {
            print_convert_help(stdout);
            return kExitConverged;
        }
        if (args.option("--title", title)) {
            have_title = true;
        } else if (args.flag("--force")) {
            force = true;
        } else if (args.at_option()) {
            args.unknown_option();
        } else if (in.empty()) {
            in = args.positional();
        } else if (out.empty()) {
            out = args.positional();
        } else {
            usage_error("convert", "too many arguments");
        }
    }
    if (in.empty() || out.empty()) usage_error("convert", "give an input file and an output file");

    // OUT = IN would replace the input (a .dat by HDF5): refused unless --force.
    check_output(out, in, force);
    ProblemPtr p = read_problem(in);
    if (have_title) {
        const frix_error err = frix_problem_set_title(p.get(), title.c_str());
        if (err != FRIX_OK) fail("convert: --title: " + library_message(err));
    }
    const frix_error err =
        frix_fclib_write(out.c_str(), p.get(), nullptr, nullptr, nullptr, 0, nullptr, nullptr, nullptr);
    if (err != FRIX_OK) fail("cannot write " + out + ": " + library_message(err));
    std::printf("%s: %s problem%s, %lld contacts, written as FCLIB to %s\n", in.c_str(),
                kind_name(frix_problem_get_kind(p.get())),
                frix_problem_mu_s(p.get()) != nullptr ? " with spinning friction" : "",
                static_cast<long long>(frix_problem_contacts(p.get())), out.c_str());
    return kExitConverged;
}

}  // namespace frix_cli
