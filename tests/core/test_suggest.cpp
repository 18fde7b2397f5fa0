// SPDX-License-Identifier: MIT
// "Did you mean" (talus/suggest.hpp): the optimal-string-alignment distance against values
// worked out by hand, and which names are offered.
#include <catch2/catch.hpp>

#include "talus/suggest.hpp"

using talus::closeNames;
using talus::didYouMean;
using talus::editDistance;

TEST_CASE("edit distance: insertions, deletions, substitutions, swaps of neighbours",
          "[core][suggest]") {
    CHECK(editDistance("", "") == 0);
    CHECK(editDistance("", "abc") == 3);  // three insertions
    CHECK(editDistance("linear", "linear") == 0);
    CHECK(editDistance("LINEAR", "linear") == 0);  // case does not count
    CHECK(editDistance("linaer", "linear") == 1);  // a swap of neighbours "ae" <-> "ea"
    CHECK(editDistance("knn", "kn") == 1);         // a deletion
    CHECK(editDistance("fric", "frac") == 1);      // a substitution
    // The textbook pair: k->s, e->i, insert g.
    CHECK(editDistance("kitten", "sitting") == 3);
    // Optimal string alignment edits no substring twice: "ca" -> "abc" takes 3 (a swap and an
    // insertion between the swapped letters would be 2, which this distance does not allow).
    CHECK(editDistance("ca", "abc") == 3);
}

TEST_CASE("close names: within a third of the length, nearest first, at most three",
          "[core][suggest]") {
    const std::vector<std::string> props = {"kn",        "ks",        "fric",
                                            "dp_nratio", "dp_sratio", "dp_mode"};
    CHECK(closeNames("knn", props) == std::vector<std::string>{"kn"});
    CHECK(closeNames("kx", props) == std::vector<std::string>{"kn", "ks"});  // both 1 edit
    CHECK(closeNames("dp_nratoi", props) == std::vector<std::string>{"dp_nratio", "dp_sratio"});
    CHECK(closeNames("kn", props).empty());        // a known name: nothing to suggest
    CHECK(closeNames("damping", props).empty());   // nothing within 2 edits
    CHECK(closeNames("friction", props).empty());  // "fric" is 4 deletions away
    CHECK(didYouMean("linaer", {"hertz", "linear", "power"}) == "; did you mean 'linear'?");
    CHECK(didYouMean("kx", props) == "; did you mean 'kn' or 'ks'?");
    CHECK(didYouMean("a_b", {"a_c", "a_d", "a_e", "a_f"}) ==
          "; did you mean 'a_c', 'a_d' or 'a_e'?");
    CHECK(didYouMean("zzz", props).empty());
}
