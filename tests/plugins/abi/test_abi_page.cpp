// SPDX-License-Identifier: MIT
//
// The numbers docs/plugin-abi.md quotes, checked against the headers a plugin compiles with: the
// ABI version ("now N", the list of minor versions), the struct sizes of the PluginInfo table,
// the host's side of every refusal message it shows ("... but this Talus has N"), the lane
// state limit and the build key's ABI suffix. A rule that no longer finds its sentence fails
// too, so that rewording the page cannot leave a number unchecked.
#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/plugin_registry.hpp"

namespace {

/// The page's text, read once: the matches below point into it, so it must outlive them (a
/// temporary string would leave them dangling).
const std::string& page() {
    static const std::string text = [] {
        std::ifstream in(TALUS_ABI_PAGE);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }();
    REQUIRE(!text.empty());
    return text;
}

/// Every match of `pattern` in `text`.
std::vector<std::smatch> matches(const std::string& text, const std::string& pattern) {
    const std::regex re(pattern);
    return {std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()};
}

/// The size the host sees of the struct the page names.
long sizeOf(const std::string& name) {
    if (name == "FdBlock") return static_cast<long>(sizeof(talus::FdBlock));
    if (name == "PropBlock") return static_cast<long>(sizeof(talus::PropBlock));
    if (name == "PluginInfo") return static_cast<long>(sizeof(talus::PluginInfo));
    if (name == "LaneLaw") return static_cast<long>(sizeof(talus::LaneLaw));
    FAIL("the page quotes the size of " << name << ", which this test does not know");
    return -1;
}

const std::string kHostAbi =
    std::to_string(TALUS_ABI_MAJOR) + "." + std::to_string(TALUS_ABI_MINOR);

/// True when `text` names every minor version 1.1 ... 1.MINOR (the page's version history).
bool listsEveryMinor(const std::string& text) {
    for (int minor = 1; minor <= TALUS_ABI_MINOR; ++minor)
        if (text.find(std::to_string(TALUS_ABI_MAJOR) + "." + std::to_string(minor)) ==
            std::string::npos)
            return false;
    return true;
}

}  // namespace

TEST_CASE("plugin-abi.md: the ABI version it quotes is the header's", "[abi][docs]") {
    const std::string doc = page();
    const auto major = matches(doc, R"(`TALUS_ABI_MAJOR`[^|\n]*\(now (\d+)\))");
    REQUIRE(major.size() == 1);
    CHECK(std::stol(major[0][1]) == TALUS_ABI_MAJOR);

    // "(now 3: 1.1 added ...; 1.2 ...; 1.3 ...)" in the PluginInfo table and
    // "(`TALUS_ABI_MINOR`, 3 now: 1.1 ..., 1.2 ..., 1.3 ...)" under Versioning.
    auto minors = matches(doc, R"(`TALUS_ABI_MINOR`[^|\n(]*\(now (\d+)([^|\n]*))");
    const auto versioning = matches(doc, R"(\(`TALUS_ABI_MINOR`, (\d+) now([^)\n]*))");
    minors.insert(minors.end(), versioning.begin(), versioning.end());
    REQUIRE(minors.size() == 2);
    for (const auto& m : minors) {
        INFO(m.str());
        CHECK(std::stol(m[1]) == TALUS_ABI_MINOR);
        CHECK(listsEveryMinor(m[2]));
    }
}

TEST_CASE("plugin-abi.md: the struct sizes in the PluginInfo table are the header's",
          "[abi][docs]") {
    // | `sizeof_fdblock` | `uint32_t` | `sizeof(FdBlock)` in the plugin's compilation (240 on
    // x86-64) |
    const auto rows = matches(
        page(), R"(\| `sizeof_\w+` \| `uint32_t` \| `sizeof\((\w+)\)`[^|(]*\((\d+)[^|]*\|)");
    REQUIRE(rows.size() == 3);  // FdBlock, PropBlock, PluginInfo
#if defined(__x86_64__)
    for (const auto& r : rows) {
        INFO(r.str());
        CHECK(std::stol(r[2]) == sizeOf(r[1]));
    }
#else
    WARN("the page quotes the sizes on x86-64; not compared on this machine");
#endif
}

TEST_CASE("plugin-abi.md: every refusal it shows quotes this host's side", "[abi][docs]") {
    const std::string doc = page();
    // "... was built for sizeof(FdBlock) = 232 but this Talus has 240; rebuild ..."
    const auto sizes = matches(doc, R"(sizeof\((\w+)\) = (\d+) but this Talus has (\d+))");
    CHECK(sizes.size() >= 3);  // PluginInfo, FdBlock, PropBlock
#if defined(__x86_64__)
    for (const auto& s : sizes) {
        INFO(s.str());
        CHECK(std::stol(s[3]) == sizeOf(s[1]));
        CHECK(std::stol(s[2]) != std::stol(s[3]));  // the example is a refusal
    }
#endif
    // "... was built for plugin ABI 2.0 but this Talus has 1.3; ..." and the minor one, whose
    // plugin version must be one the host refuses.
    const auto abi = matches(
        doc, R"(plugin ABI (\d+)\.(\d+) but this Talus has (\d+\.\d+)( \(older minor version\))?)");
    CHECK(abi.size() == 2);
    for (const auto& a : abi) {
        INFO(a.str());
        CHECK(a[3] == kHostAbi);
        const long major = std::stol(a[1]), minor = std::stol(a[2]);
        if (a[4].matched)
            CHECK((major == TALUS_ABI_MAJOR && minor > TALUS_ABI_MINOR));
        else
            CHECK(major != TALUS_ABI_MAJOR);
    }
    const auto dim = matches(doc, R"(dimension (\d+) but this Talus has (\d+))");
    REQUIRE(dim.size() == 1);
    CHECK(std::stol(dim[0][2]) == TALUS_DIM);
    CHECK(std::stol(dim[0][1]) != TALUS_DIM);
}

TEST_CASE("plugin-abi.md: the lane state limit and the build key's ABI are the header's",
          "[abi][docs]") {
    const std::string doc = page();
    const auto lanes = matches(doc, R"(`state_size` is outside 1 to (\d+))");
    REQUIRE(lanes.size() == 1);
    CHECK(std::stol(lanes[0][1]) == talus::kMaxLaneStateSize);
    // Build keys end in "|abi<major>" (written "\|abi1" inside the tables).
    const auto keys = matches(doc, R"(\|ptr\d+\\?\|\d+\\?\|abi(\d+))");
    CHECK(keys.size() >= 2);
    for (const auto& k : keys) {
        INFO(k.str());
        CHECK(std::stol(k[1]) == TALUS_ABI_MAJOR);
    }
}
