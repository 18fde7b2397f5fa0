// SPDX-License-Identifier: MIT
//
// Every way a plugin library can be refused, and the registry's look-up rules
// (docs/plugin-abi.md, "What the host refuses"). Each refusal must name the file and, where two
// builds disagree, both values, so that the user knows which side to rebuild. Every test uses a
// registry of its own, so nothing here touches PluginRegistry::global().
#include <elf.h>
#include <link.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

using talus::PluginError;
using talus::PluginRegistry;

namespace {

std::string canonical(const std::string& path) {
    char* r = ::realpath(path.c_str(), nullptr);
    if (!r) return path;
    std::string s(r);
    std::free(r);
    return s;
}

/// Path of a test library built from bad_plugin.cpp.
std::string lib(const std::string& stem) {
    return canonical(std::string(TEST_PLUGIN_DIR) + "/libtalus_" + stem + ".so");
}

/// The message of the PluginError that `fn` throws (fails the test if it throws nothing else).
template <class F>
std::string pluginErrorOf(F&& fn) {
    try {
        fn();
    } catch (const PluginError& e) {
        return e.what();
    }
    FAIL("expected a PluginError");
    return {};
}

/// Message of loading `path` into a fresh registry.
std::string refusalOf(const std::string& path) {
    PluginRegistry reg;
    return pluginErrorOf([&] { reg.load(path); });
}

std::string hostAbi() {
    return std::to_string(TALUS_ABI_MAJOR) + "." + std::to_string(TALUS_ABI_MINOR);
}

/// A scratch directory, removed with its files at the end of the test.
struct TempDir {
    std::string path;
    std::vector<std::string> files;
    TempDir() {
        std::string tmpl = "/tmp/talus_abi_XXXXXX";
        if (const char* t = std::getenv("TMPDIR")) tmpl = std::string(t) + "/talus_abi_XXXXXX";
        std::vector<char> buf(tmpl.begin(), tmpl.end());
        buf.push_back('\0');
        REQUIRE(::mkdtemp(buf.data()) != nullptr);
        path = canonical(buf.data());
    }
    std::string write(const std::string& name, const std::string& text) {
        const std::string p = path + "/" + name;
        std::ofstream(p) << text;
        files.push_back(p);
        return p;
    }
    ~TempDir() {
        for (const auto& f : files) std::remove(f.c_str());
        ::rmdir(path.c_str());
    }
};

/// Sets an environment variable for the scope of a test.
struct ScopedEnv {
    std::string name;
    bool had = false;
    std::string old;
    ScopedEnv(const char* n, const std::string& value) : name(n) {
        if (const char* v = std::getenv(n)) had = true, old = v;
        ::setenv(n, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (had)
            ::setenv(name.c_str(), old.c_str(), 1);
        else
            ::unsetenv(name.c_str());
    }
};

}  // namespace

using Catch::Matchers::Contains;

// ----------------------------------------------------------------------- files that are no plugin

TEST_CASE("loading a missing file names it", "[abi][loading]") {
    const std::string path = std::string(TEST_PLUGIN_DIR) + "/libtalus_does_not_exist.so";
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains("no such file"));
    CHECK_THAT(msg, Contains(path));
}

TEST_CASE("a file that is not a shared library is refused with the loader's reason",
          "[abi][loading]") {
    TempDir dir;
    const std::string path = dir.write("libtalus_text.so", "this is not an ELF file\n");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains("cannot load"));
    CHECK_THAT(msg, Contains(path));
    // the dynamic loader's own words follow the file name
    CHECK(msg.size() > msg.find(path) + path.size() + 3);
}

TEST_CASE("a library without the entry point is refused", "[abi][loading]") {
    const std::string path = lib("bad_no_entry");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("is not a Talus plugin"));
    CHECK_THAT(msg, Contains(TALUS_PLUGIN_ENTRY));
    CHECK_THAT(msg, Contains("TALUS_PLUGIN_EXPORT"));
}

TEST_CASE("an entry point returning null is refused", "[abi][loading]") {
    const std::string path = lib("bad_null_info");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("talus_plugin_info() returned null"));
}

// ----------------------------------------------------------------------- version and layout checks

TEST_CASE("an ABI major mismatch names both versions", "[abi][loading]") {
    const std::string path = lib("bad_abi_major");
    const std::string msg = refusalOf(path);
    const std::string plugin =
        std::to_string(TALUS_ABI_MAJOR + 1) + "." + std::to_string(TALUS_ABI_MINOR);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("plugin ABI " + plugin));
    CHECK_THAT(msg, Contains("this Talus has " + hostAbi()));
    CHECK_THAT(msg, Contains("rebuild the plugin"));
}

TEST_CASE("a plugin built for a newer minor ABI than the host is refused", "[abi][loading]") {
    const std::string path = lib("bad_abi_minor");
    const std::string msg = refusalOf(path);
    const std::string plugin =
        std::to_string(TALUS_ABI_MAJOR) + "." + std::to_string(TALUS_ABI_MINOR + 1);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("plugin ABI " + plugin));
    CHECK_THAT(msg, Contains("this Talus has " + hostAbi()));
}

TEST_CASE("a bad lane law (ABI 1.2) is refused with what is wrong", "[abi][loading]") {
    const std::string size = refusalOf(lib("bad_lanes_size"));
    CHECK_THAT(size, Contains("model 'probe': talus_plugin_lanes returned a bad LaneLaw"));
    CHECK_THAT(size, Contains("sizeof(LaneLaw) = " + std::to_string(sizeof(talus::LaneLaw) + 8)));
    CHECK_THAT(size, Contains("rebuild the plugin"));
    CHECK_THAT(refusalOf(lib("bad_lanes_state")), Contains("state_size = 0 (must be 1 to 256)"));
    CHECK_THAT(refusalOf(lib("bad_lanes_null")),
               Contains("pack, unpack and law must all be given"));
}

TEST_CASE("struct size mismatches name the struct and both sizes", "[abi][loading]") {
    struct Case {
        const char* stem;
        const char* what;
        std::size_t host;
    };
    const Case cases[] = {
        {"bad_sizeof_fdblock", "sizeof(FdBlock)", sizeof(talus::FdBlock)},
        {"bad_sizeof_propblock", "sizeof(PropBlock)", sizeof(talus::PropBlock)},
        {"bad_sizeof_plugininfo", "sizeof(PluginInfo)", sizeof(talus::PluginInfo)},
    };
    for (const Case& c : cases) {
        INFO(c.stem);
        const std::string path = lib(c.stem);
        const std::string msg = refusalOf(path);
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains(std::string(c.what) + " = " + std::to_string(c.host + 8)));
        CHECK_THAT(msg, Contains("this Talus has " + std::to_string(c.host)));
    }
}

TEST_CASE("a plugin of another dimension is refused", "[abi][loading]") {
    const std::string path = lib("bad_dim");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("dimension 3"));
    CHECK_THAT(msg, Contains("this Talus has " + std::to_string(TALUS_DIM)));
}

TEST_CASE("a plugin with another build key is refused", "[abi][loading]") {
    const std::string path = lib("bad_build_key");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("build key itanium-othercc|cxx11abi=0|ptr8|1234|abi1"));
    CHECK_THAT(msg, Contains(std::string("this Talus has ") + TALUS_BUILD_KEY));
}

// ----------------------------------------------------------------------- model table checks

TEST_CASE("a plugin without models or factories is refused", "[abi][loading]") {
    SECTION("model_count = 0") {
        const std::string path = lib("bad_no_models");
        const std::string msg = refusalOf(path);
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains("offers no models"));
        CHECK_THAT(msg, Contains("model_count = 0"));
    }
    SECTION("create_prototype missing") {
        const std::string path = lib("bad_null_create");
        const std::string msg = refusalOf(path);
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains("create_prototype"));
    }
    SECTION("destroy_prototype missing") {
        const std::string path = lib("bad_null_destroy");
        const std::string msg = refusalOf(path);
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains("destroy_prototype"));
    }
}

TEST_CASE("create_prototype returning null is refused", "[abi][loading]") {
    const std::string path = lib("bad_null_prototype");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("create_prototype(0) returned null"));
}

TEST_CASE("a model with an empty name is refused", "[abi][loading]") {
    const std::string path = lib("bad_empty_name");
    const std::string msg = refusalOf(path);
    CHECK_THAT(msg, Contains(path));
    CHECK_THAT(msg, Contains("model 0 has no name"));
}

TEST_CASE("duplicate model names are refused", "[abi][loading]") {
    SECTION("within one library") {
        const std::string path = lib("bad_duplicate_inside");
        PluginRegistry reg;
        const std::string msg = pluginErrorOf([&] { reg.load(path); });
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains("defines model 'dup_inner' twice"));
        CHECK(reg.modelNames().empty());  // nothing of the refused library stays registered
    }
    SECTION("across two libraries, also when the case differs") {
        const std::string first = lib("twin_a");
        const std::string second = GENERATE(std::string("twin_b"), std::string("twin_upper"));
        const std::string path = lib(second);
        PluginRegistry reg;
        REQUIRE(reg.load(first) == std::vector<std::string>{"twin"});
        const std::string msg = pluginErrorOf([&] { reg.load(path); });
        CHECK_THAT(msg, Contains(path));
        CHECK_THAT(msg, Contains(first));
        CHECK_THAT(msg, Contains("already defined by"));
        CHECK_THAT(msg, Contains("plugin version 1.0.0-a"));
        CHECK_THAT(msg, Contains("model names must be unique"));
        // the first library's model is still the one found
        REQUIRE(reg.modelNames() == std::vector<std::string>{"twin"});
        CHECK(reg.find("twin").library == first);
        CHECK(reg.find("twin").plugin_version == "1.0.0-a");
    }
}

TEST_CASE("a refused library leaves the registry usable", "[abi][loading]") {
    PluginRegistry reg;
    CHECK_THROWS_AS(reg.load(lib("bad_abi_major")), PluginError);
    CHECK_THROWS_AS(reg.load(lib("bad_duplicate_inside")), PluginError);
    CHECK(reg.load(lib("mixed_case")) == std::vector<std::string>{"MixedCase"});
    auto proto = reg.createPrototype(reg.find("mixedcase"));
    REQUIRE(proto);
    CHECK(std::string(proto->Name()) == "MixedCase");
}

// ----------------------------------------------------------------------- loading and look-up

TEST_CASE("loading the same file twice is a no-op", "[abi][loading]") {
    PluginRegistry reg;
    const std::string path = lib("twin_a");
    CHECK(reg.load(path) == std::vector<std::string>{"twin"});
    CHECK(reg.load(path).empty());
    // the same file through another spelling of its path
    const std::string dir = TEST_PLUGIN_DIR;
    const std::string base = dir.substr(dir.find_last_of('/') + 1);
    CHECK(reg.load(dir + "/../" + base + "/./libtalus_twin_a.so").empty());
    CHECK(reg.modelNames() == std::vector<std::string>{"twin"});
    CHECK(reg.find("twin").library == path);
}

TEST_CASE("model look-up is case-insensitive and keeps the model's spelling", "[abi][loading]") {
    PluginRegistry reg;
    reg.load(lib("mixed_case"));
    const talus::ModelFactory& a = reg.find("MixedCase");
    const talus::ModelFactory& b = reg.find("mixedcase");
    const talus::ModelFactory& c = reg.find("MIXEDCASE");
    CHECK(&a == &b);
    CHECK(&a == &c);
    CHECK(a.name == "MixedCase");
    CHECK(reg.tryFind("mIxEdCaSe") == &a);
    CHECK(reg.tryFind("mixed") == nullptr);
}

TEST_CASE("find of an unknown model lists the loaded models and the search path",
          "[abi][loading]") {
    TempDir dir;
    PluginRegistry reg;
    reg.addSearchDirectory(dir.path);
    reg.load(lib("mixed_case"));
    reg.load(lib("twin_a"));
    const std::string msg = pluginErrorOf([&] { reg.find("NoSuchModel"); });
    CHECK_THAT(msg, Contains("unknown contact model 'NoSuchModel'"));
    CHECK_THAT(msg, Contains("loaded: MixedCase, twin"));
    CHECK_THAT(msg, Contains("libtalus_nosuchmodel.so"));
    CHECK_THAT(msg, Contains(dir.path));
    CHECK_THAT(msg, Contains("TALUS_PLUGIN_PATH"));
    // the directory added last is searched first
    REQUIRE_FALSE(reg.searchDirectories().empty());
    CHECK(reg.searchDirectories().front() == dir.path);
}

TEST_CASE("find searches TALUS_PLUGIN_PATH for libtalus_<name>.so", "[abi][loading]") {
    const std::string search = canonical(TEST_SEARCH_DIR);
    ScopedEnv env("TALUS_PLUGIN_PATH", "/nonexistent/talus/plugins::" + search);
    PluginRegistry reg;  // reads the variable when constructed
    const auto& dirs = reg.searchDirectories();
    REQUIRE(dirs.size() >= 2);
    CHECK(dirs[0] == "/nonexistent/talus/plugins");  // in order, empty entries skipped
    CHECK(dirs[1] == search);
    CHECK(reg.tryFind("pathmodel") == nullptr);

    SECTION("found by name, in any case") {
        const talus::ModelFactory& f =
            reg.find(GENERATE(std::string("pathmodel"), std::string("PathModel")));
        CHECK(f.name == "pathmodel");
        CHECK(f.library == search + "/libtalus_pathmodel.so");
    }
    SECTION("a bad library found on the path is refused with its name and versions") {
        const std::string msg = pluginErrorOf([&] { reg.find("badpath"); });
        CHECK_THAT(msg, Contains(search + "/libtalus_badpath.so"));
        CHECK_THAT(msg, Contains("this Talus has " + hostAbi()));
    }
    SECTION("an unknown name reports the directories of the variable") {
        const std::string msg = pluginErrorOf([&] { reg.find("absent"); });
        CHECK_THAT(msg, Contains("/nonexistent/talus/plugins:" + search));
    }
}

TEST_CASE("a well-formed test plugin exposes its prototype and metadata", "[abi][loading]") {
    PluginRegistry reg;
    reg.load(lib("twin_a"));
    const talus::ModelFactory& f = reg.find("twin");
    REQUIRE(f.info != nullptr);
    CHECK(f.info->abi_major == TALUS_ABI_MAJOR);
    CHECK(f.info->sizeof_fdblock == sizeof(talus::FdBlock));
    CHECK(std::string(f.info->build_key) == TALUS_BUILD_KEY);
    REQUIRE(f.reference != nullptr);
    CHECK(std::string(f.reference->PropNames()) == "kn");
    const talus::PropInfo* kn = f.reference->PropInfoAt(0);
    REQUIRE(kn != nullptr);
    CHECK(std::string(kn->units) == "N/m");
    CHECK((kn->flags & talus::kPropInheritable) != 0);
    CHECK(f.reference->PropInfoAt(1) == nullptr);
    // a prototype of its own, destroyed by the library
    auto p = reg.createPrototype(f);
    CHECK(p.get() != f.reference);
    CHECK(p->AcceptProp(0, -1.0) != 0);
    CHECK_THAT(std::string(p->LastError()), Contains("'kn' must be >= 0"));
}

// ----------------------------------------------------------------------- damaged libraries
// A library cut short (an interrupted copy, a full disk) used to kill the host with SIGBUS inside
// dlopen, which maps segments past the end of the file. The host now reads the
// ELF headers first; every cut of a real plugin must be a PluginError naming the file. If the
// check misses a case, this test dies with SIGBUS instead of failing politely.

namespace {

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Byte offsets at which the segments and the section header table of an ELF image end: a cut
/// one byte short of each is the most treacherous truncation.
std::vector<std::size_t> elfBoundaries(const std::string& image) {
    std::vector<std::size_t> ends;
    ElfW(Ehdr) eh{};
    REQUIRE(image.size() >= sizeof eh);
    std::memcpy(&eh, image.data(), sizeof eh);
    for (std::size_t i = 0; i < eh.e_phnum; ++i) {
        ElfW(Phdr) ph{};
        REQUIRE(eh.e_phoff + (i + 1) * sizeof ph <= image.size());
        std::memcpy(&ph, image.data() + eh.e_phoff + i * sizeof ph, sizeof ph);
        if (ph.p_filesz > 0) ends.push_back(ph.p_offset + ph.p_filesz);
    }
    ends.push_back(eh.e_phoff + eh.e_phnum * sizeof(ElfW(Phdr)));
    ends.push_back(eh.e_shoff + eh.e_shnum * sizeof(ElfW(Shdr)));
    return ends;
}

}  // namespace

TEST_CASE("a truncated plugin library is refused before dlopen, never a crash",
          "[abi][loading][elf]") {
    const std::string image = readAll(LINEAR_PLUGIN);
    REQUIRE(image.size() > 20480);  // the cuts below must all be real truncations
    TempDir dir;
    // The whole copy loads: the check refuses no sound library.
    {
        const std::string whole = dir.write("libtalus_whole.so", image);
        PluginRegistry reg;
        CHECK(reg.load(whole) == std::vector<std::string>{"linear"});
    }
    std::vector<std::size_t> cuts = {0,
                                     4,
                                     16,
                                     63,
                                     64,
                                     100,
                                     1024,
                                     2048,
                                     4096,
                                     8192,
                                     12288,
                                     16384,
                                     20480,
                                     image.size() / 2,
                                     image.size() - 1};
    for (std::size_t end : elfBoundaries(image))
        if (end >= 1 && end <= image.size()) cuts.push_back(end - 1);
    for (std::size_t cut : cuts) {
        if (cut >= image.size()) continue;
        INFO("library cut to " << cut << " of " << image.size() << " bytes");
        const std::string path =
            dir.write("libtalus_cut" + std::to_string(cut) + ".so", image.substr(0, cut));
        const std::string msg = refusalOf(path);
        CHECK_THAT(msg, Contains("cannot load '" + path + "'"));
        CHECK_THAT(msg, Contains("ELF"));
        CHECK_THAT(msg, Contains(std::to_string(cut) + " bytes"));
    }
}

TEST_CASE("an ELF file of another class or type is refused with the reason",
          "[abi][loading][elf]") {
    std::string image = readAll(LINEAR_PLUGIN);
    REQUIRE(image.size() > 64);
    TempDir dir;
    SECTION("32-bit class") {
        image[EI_CLASS] = ELFCLASS32;
        CHECK_THAT(refusalOf(dir.write("libtalus_c32.so", image)), Contains("32-bit"));
    }
    SECTION("an executable, not a shared library") {
        ElfW(Ehdr) eh{};
        std::memcpy(&eh, image.data(), sizeof eh);
        eh.e_type = ET_EXEC;
        std::memcpy(&image[0], &eh, sizeof eh);
        CHECK_THAT(refusalOf(dir.write("libtalus_exec.so", image)),
                   Contains("not a shared library"));
    }
    SECTION("a segment beyond the end of the file") {
        ElfW(Ehdr) eh{};
        std::memcpy(&eh, image.data(), sizeof eh);
        ElfW(Phdr) ph{};
        std::memcpy(&ph, image.data() + eh.e_phoff, sizeof ph);
        ph.p_filesz = image.size() + 4096;  // a header claiming more than the file holds
        ph.p_memsz = std::max<decltype(ph.p_memsz)>(ph.p_memsz, ph.p_filesz);
        std::memcpy(&image[eh.e_phoff], &ph, sizeof ph);
        CHECK_THAT(refusalOf(dir.write("libtalus_seg.so", image)), Contains("segment 0"));
    }
}
