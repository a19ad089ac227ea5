#include "solvers/kit/line_search.hpp"

#include <frix/frix_options.h>

namespace frix::kit {

Search search_of(int64_t line_search, int64_t max_trials) {
    Search s;
    s.kind = line_search == FRIX_LINE_SEARCH_NONE         ? Search::kNone
             : line_search == FRIX_LINE_SEARCH_ARMIJO      ? Search::kArmijo
             : line_search == FRIX_LINE_SEARCH_NONMONOTONE ? Search::kNonmonotone
                                                           : Search::kGoldsteinPrice;
    s.max_trials = (int)max_trials;
    return s;
}

Search armijo_search_of(int64_t line_search, int64_t max_trials) {
    Search s = search_of(line_search, max_trials);
    if (s.kind == Search::kGoldsteinPrice) s.kind = Search::kArmijo, s.c = kGoldsteinM1;
    return s;
}

Search newton_merit_search_of(int64_t line_search, int64_t max_trials) {
    Search s;
    s.kind = line_search == FRIX_LINE_SEARCH_NONE ? Search::kNone : Search::kNewtonMerit;
    s.max_trials = (int)max_trials;
    return s;
}

SearchResult line_search(const Search &s, const std::function<double(double)> &merit, double psi, double slope,
                         const MeritHistory &history, int64_t &trials) {
    SearchResult none;
    switch (s.kind) {
        case Search::kNone: none.accepted = true, none.t = 1.0; return none;
        case Search::kNewtonMerit: return backtrack(merit, psi, Decrease{psi, s.c, 0.0, true}, s.max_trials, trials);
        default: break;
    }
    if (!(slope < 0.0)) return none;
    if (s.kind == Search::kGoldsteinPrice) return goldstein_price(merit, psi, slope, s.max_trials, trials);
    // Non-monotone: against the largest of the last merits, so that a full step may climb
    // for a while over the kinks of the merit.
    const double ref = s.kind == Search::kNonmonotone ? history.reference(psi) : psi;
    return backtrack(merit, psi, Decrease{ref, s.c, slope}, s.max_trials, trials);
}

}  // namespace frix::kit
