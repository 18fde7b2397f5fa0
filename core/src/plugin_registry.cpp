// SPDX-License-Identifier: MIT
//
// dlopen-based plugin loading with the checks of docs/plugin-abi.md "What the host refuses".
// Every refusal names the file and both sides' values, so a user can tell which build to redo.
#include "talus/plugin_registry.hpp"

#include <dirent.h>
#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <link.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "talus/errors.hpp"
#include "talus/suggest.hpp"

namespace talus {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool fileExists(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string canonical(const std::string& path) {
    char* r = ::realpath(path.c_str(), nullptr);
    if (!r) return path;
    std::string s(r);
    std::free(r);
    return s;
}

// ---------------------------------------------------------------------------- ELF pre-check
// dlopen maps a library's segments straight from the file: a segment that reaches past the end
// of a truncated file is mapped all the same, and the loader's first read of it (relocation,
// the dynamic section) kills the process with SIGBUS instead of returning an error. So the host
// reads the headers itself (with pread, never mmap) and refuses a file whose header, program
// headers, section header table or any segment's file range does not lie inside the file.
// The loader's own checks (machine, dependencies, symbols) stay dlopen's: they fail cleanly.

using Ehdr = ElfW(Ehdr);
using Phdr = ElfW(Phdr);
using Shdr = ElfW(Shdr);
#if __SIZEOF_POINTER__ == 8
constexpr unsigned char kHostElfClass = ELFCLASS64;
#else
constexpr unsigned char kHostElfClass = ELFCLASS32;
#endif
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr unsigned char kHostElfData = ELFDATA2LSB;
#else
constexpr unsigned char kHostElfData = ELFDATA2MSB;
#endif

/// True when [offset, offset + count * entry) lies inside a file of `size` bytes (no overflow).
bool inside(uint64_t offset, uint64_t count, uint64_t entry, uint64_t size) {
    if (offset > size) return false;
    if (entry != 0 && count > (size - offset) / entry) return false;
    return true;
}

/// Reads `n` bytes at `offset`; false on a short read.
bool readAt(int fd, void* buf, std::size_t n, uint64_t offset) {
    auto* p = static_cast<char*>(buf);
    while (n > 0) {
        const ssize_t got = ::pread(fd, p, n, static_cast<off_t>(offset));
        if (got <= 0) return false;
        p += got, n -= static_cast<std::size_t>(got), offset += static_cast<uint64_t>(got);
    }
    return true;
}

/// Empty if `path` looks like a complete shared object of this host's ELF class, else why not.
std::string elfProblem(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::string("cannot open it: ") + std::strerror(errno);
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) return std::string("cannot stat it: ") + std::strerror(errno);
    const auto size = static_cast<uint64_t>(st.st_size);
    const std::string of_size = " (the file has " + std::to_string(size) + " bytes";
    unsigned char ident[EI_NIDENT] = {};
    if (size < EI_NIDENT || !readAt(fd, ident, EI_NIDENT, 0) ||
        std::memcmp(ident, ELFMAG, SELFMAG) != 0)
        return "not an ELF file (no ELF magic number" + of_size + ")";
    if (ident[EI_CLASS] != kHostElfClass)
        return std::string("ELF class ") + (ident[EI_CLASS] == ELFCLASS32 ? "32-bit" : "64-bit") +
               " does not match this " + std::to_string(8 * sizeof(void*)) + "-bit Talus";
    if (ident[EI_DATA] != kHostElfData) return "ELF byte order does not match this Talus";
    Ehdr eh{};
    if (size < sizeof eh || !readAt(fd, &eh, sizeof eh, 0))
        return "truncated ELF file: the ELF header needs " + std::to_string(sizeof eh) + " bytes" +
               of_size + ")";
    if (eh.e_type != ET_DYN)
        return "not a shared library (ELF type " + std::to_string(eh.e_type) + ")";
    if (eh.e_ehsize < sizeof eh)
        return "corrupt ELF header (e_ehsize " + std::to_string(eh.e_ehsize) + ")";
    if (eh.e_phnum == 0 || eh.e_phentsize != sizeof(Phdr))
        return "corrupt ELF header (" + std::to_string(eh.e_phnum) + " program headers of " +
               std::to_string(eh.e_phentsize) + " bytes)";
    if (!inside(eh.e_phoff, eh.e_phnum, sizeof(Phdr), size))
        return "truncated ELF file: its program headers end at byte " +
               std::to_string(eh.e_phoff + uint64_t(eh.e_phnum) * sizeof(Phdr)) + of_size + ")";
    if (eh.e_shoff != 0) {
        // e_shnum == 0 with a table means more than 0xff00 sections, counted in entry 0.
        const uint64_t shnum = eh.e_shnum != 0 ? eh.e_shnum : 1;
        if (eh.e_shentsize != sizeof(Shdr))
            return "corrupt ELF header (section headers of " + std::to_string(eh.e_shentsize) +
                   " bytes)";
        if (!inside(eh.e_shoff, shnum, sizeof(Shdr), size))
            return "truncated ELF file: its section header table ends at byte " +
                   std::to_string(eh.e_shoff + shnum * sizeof(Shdr)) + of_size + ")";
    }
    std::vector<Phdr> ph(eh.e_phnum);
    if (!readAt(fd, ph.data(), ph.size() * sizeof(Phdr), eh.e_phoff))
        return "cannot read its program headers";
    bool any_load = false;
    for (std::size_t i = 0; i < ph.size(); ++i) {
        const Phdr& h = ph[i];
        if (h.p_type == PT_NULL) continue;
        any_load |= h.p_type == PT_LOAD;
        if (!inside(h.p_offset, h.p_filesz, 1, size))
            return "truncated ELF file: segment " + std::to_string(i) +
                   (h.p_type == PT_LOAD ? " (PT_LOAD)" : "") + " spans bytes " +
                   std::to_string(h.p_offset) + " to " +
                   std::to_string(uint64_t(h.p_offset) + h.p_filesz) + of_size + ")";
        if (h.p_type == PT_LOAD && h.p_filesz > h.p_memsz)
            return "corrupt ELF file: segment " + std::to_string(i) +
                   " holds more bytes in the file than in memory";
    }
    if (!any_load) return "corrupt ELF file: no loadable segment";
    return {};
}

// ---------------------------------------------------------------------------- load stages
// PluginRegistry::load runs these in order; each throws a PluginError naming the file at the
// first refusal (docs/plugin-abi.md, "What the host refuses", lists them in this order).

/// The file as given -> its canonical path (symbolic links and `..` resolved).
std::string checkedPath(const std::string& path_in) {
    if (!fileExists(path_in)) {
        struct stat st {};
        if (::stat(path_in.c_str(), &st) == 0)
            throw PluginError("load_plugin: '" + path_in + "' is not a regular file");
        throw PluginError("load_plugin: no such file '" + path_in + "'");
    }
    return canonical(path_in);
}

/// Maps the library, after refusing a damaged file before dlopen sees it (see elfProblem).
void* openLibrary(const std::string& path) {
    const std::string elf = elfProblem(path);
    if (!elf.empty()) throw PluginError("load_plugin: cannot load '" + path + "': " + elf);
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = ::dlerror();
        throw PluginError("load_plugin: cannot load '" + path + "': " + (why ? why : "unknown"));
    }
    return handle;
}

/// The library's PluginInfo, refused when it was built for another host (ABI version, struct
/// sizes, dimension, build key) or offers no models.
const PluginInfo* checkedInfo(const std::string& path, void* handle) {
    ::dlerror();
    auto entry = reinterpret_cast<TalusPluginInfoFn>(::dlsym(handle, TALUS_PLUGIN_ENTRY));
    if (!entry)
        throw PluginError("load_plugin: '" + path +
                          "' is not a Talus plugin: it does not export '" + TALUS_PLUGIN_ENTRY +
                          "' (declare it with TALUS_PLUGIN_EXPORT)");
    const PluginInfo* info = entry();
    auto refuse = [&](const std::string& what, const std::string& plugin, const std::string& host) {
        throw PluginError("load_plugin: '" + path + "' was built for " + what + " " + plugin +
                          " but this Talus has " + host +
                          "; rebuild the plugin against this Talus");
    };
    if (!info) throw PluginError("load_plugin: '" + path + "': talus_plugin_info() returned null");
    const std::string plugin_abi =
        std::to_string(info->abi_major) + "." + std::to_string(info->abi_minor);
    const std::string host_abi =
        std::to_string(TALUS_ABI_MAJOR) + "." + std::to_string(TALUS_ABI_MINOR);
    if (info->abi_major != TALUS_ABI_MAJOR) refuse("plugin ABI", plugin_abi, host_abi);
    if (info->abi_minor > TALUS_ABI_MINOR)
        refuse("plugin ABI", plugin_abi, host_abi + " (older minor version)");
    if (info->sizeof_plugininfo != sizeof(PluginInfo))
        refuse("sizeof(PluginInfo) =", std::to_string(info->sizeof_plugininfo),
               std::to_string(sizeof(PluginInfo)));
    if (info->dim != TALUS_DIM)
        refuse("dimension", std::to_string(info->dim), std::to_string(TALUS_DIM));
    if (info->sizeof_fdblock != sizeof(FdBlock))
        refuse("sizeof(FdBlock) =", std::to_string(info->sizeof_fdblock),
               std::to_string(sizeof(FdBlock)));
    if (info->sizeof_propblock != sizeof(PropBlock))
        refuse("sizeof(PropBlock) =", std::to_string(info->sizeof_propblock),
               std::to_string(sizeof(PropBlock)));
    if (!info->build_key || std::strcmp(info->build_key, TALUS_BUILD_KEY) != 0)
        refuse("build key", info->build_key ? info->build_key : "(none)", TALUS_BUILD_KEY);
    if (info->model_count <= 0)
        throw PluginError("load_plugin: '" + path + "' offers no models (model_count = " +
                          std::to_string(info->model_count) + ")");
    if (!info->create_prototype || !info->destroy_prototype)
        throw PluginError("load_plugin: '" + path + "': PluginInfo::" +
                          (info->create_prototype ? "destroy_prototype" : "create_prototype") +
                          " is null");
    return info;
}

/// The optional per-model entries of later minor versions; null where the library has none.
struct OptionalEntries {
    TalusPluginBatchFn batch = nullptr;    ///< ABI 1.1: batched laws ("Batched FDlaw")
    TalusPluginLanesFn lanes = nullptr;    ///< ABI 1.2: lane laws ("Lanes")
    TalusPluginKernelFn kernel = nullptr;  ///< ABI 1.3: the SDK law of the lane rows ("Kernels")
};

OptionalEntries optionalEntries(void* handle, const PluginInfo& info) {
    OptionalEntries e;
    e.batch = reinterpret_cast<TalusPluginBatchFn>(::dlsym(handle, TALUS_PLUGIN_BATCH_ENTRY));
    if (info.abi_minor >= 2)
        e.lanes = reinterpret_cast<TalusPluginLanesFn>(::dlsym(handle, TALUS_PLUGIN_LANES_ENTRY));
    if (info.abi_minor >= 3)
        e.kernel =
            reinterpret_cast<TalusPluginKernelFn>(::dlsym(handle, TALUS_PLUGIN_KERNEL_ENTRY));
    return e;
}

/// Model `index`'s prototype, refused when the library makes none.
ContactModel* makePrototype(const std::string& path, const PluginInfo& info, int32_t index) {
    ContactModel* proto = info.create_prototype(index);
    if (!proto)
        throw PluginError("load_plugin: '" + path + "': create_prototype(" + std::to_string(index) +
                          ") returned null");
    return proto;
}

/// Refuses a lane law whose layout or state size this host cannot use.
void checkLaneLaw(const std::string& path, const std::string& name, const LaneLaw& l) {
    std::string why;
    if (l.size != sizeof(LaneLaw))
        why = "sizeof(LaneLaw) = " + std::to_string(l.size) + " but this Talus has " +
              std::to_string(sizeof(LaneLaw)) + "; rebuild the plugin against this Talus";
    else if (l.state_size < 1 || l.state_size > kMaxLaneStateSize)
        why = "state_size = " + std::to_string(l.state_size) + " (must be 1 to " +
              std::to_string(kMaxLaneStateSize) + ")";
    else if (!l.pack || !l.unpack || !l.law)
        why = "pack, unpack and law must all be given";
    if (!why.empty())
        throw PluginError("load_plugin: '" + path + "': model '" + name +
                          "': talus_plugin_lanes returned a bad LaneLaw: " + why);
}

/// The factory of model `index`, whose prototype the library has made.
ModelFactory describeModel(const std::string& path, const PluginInfo& info, int32_t index,
                           ContactModel* proto, const OptionalEntries& entries) {
    ModelFactory f;
    f.name = proto->Name() ? proto->Name() : "";
    if (f.name.empty())
        throw PluginError("load_plugin: '" + path + "': model " + std::to_string(index) +
                          " has no name");
    f.library = path;
    f.plugin_version = info.plugin_version ? info.plugin_version : "";
    f.index = index;
    f.info = &info;
    f.reference = proto;
    f.batch = entries.batch ? entries.batch(index) : nullptr;
    f.lanes = entries.lanes ? entries.lanes(index) : nullptr;
    if (f.lanes) checkLaneLaw(path, f.name, *f.lanes);
    if (entries.kernel)
        if (const char* id = entries.kernel(index)) f.kernel = id;
    return f;
}

/// Refuses a model name (case-insensitive) that a loaded library or this one already uses.
void refuseNameClash(const std::string& path, const std::string& name,
                     const std::deque<ModelFactory>& loaded,
                     const std::vector<ModelFactory>& added) {
    auto clash = [&](const ModelFactory& f) { return lower(f.name) == lower(name); };
    auto it = std::find_if(loaded.begin(), loaded.end(), clash);
    if (it != loaded.end())
        throw PluginError("load_plugin: '" + path + "' defines model '" + name +
                          "', which is already defined by '" + it->library + "' (plugin version " +
                          it->plugin_version + "); model names must be unique");
    if (std::find_if(added.begin(), added.end(), clash) != added.end())
        throw PluginError("load_plugin: '" + path + "' defines model '" + name + "' twice");
}

/// TALUS_PLUGIN_PATH's directories, in order (empty entries skipped).
std::vector<std::string> pluginPathFromEnvironment() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("TALUS_PLUGIN_PATH")) {
        std::stringstream ss(env);
        std::string dir;
        while (std::getline(ss, dir, ':'))
            if (!dir.empty()) dirs.push_back(dir);
    }
    return dirs;
}

}  // namespace

struct PluginRegistry::Library {
    std::string path;
    void* handle = nullptr;
    const PluginInfo* info = nullptr;
    std::vector<ContactModel*> references;
    ~Library() {
        // Prototypes go back to the library that made them (also those of a library refused
        // half way). The library itself stays mapped: unloading code that static destructors of
        // other libraries may still reference at exit is not worth the risk, and nothing is
        // gained in a process that is ending.
        for (ContactModel* p : references)
            if (info && info->destroy_prototype) info->destroy_prototype(p);
    }
};

PluginRegistry::PluginRegistry() : m_dirs(pluginPathFromEnvironment()) {}

PluginRegistry::~PluginRegistry() = default;

PluginRegistry& PluginRegistry::global() {
    static PluginRegistry registry;
    return registry;
}

void PluginRegistry::addSearchDirectory(const std::string& dir) {
    if (std::find(m_dirs.begin(), m_dirs.end(), dir) == m_dirs.end())
        m_dirs.insert(m_dirs.begin(), dir);
}

void PluginRegistry::appendSearchDirectory(const std::string& dir) {
    if (std::find(m_dirs.begin(), m_dirs.end(), dir) == m_dirs.end()) m_dirs.push_back(dir);
}

std::vector<std::string> PluginRegistry::load(const std::string& path_in) {
    const std::string path = checkedPath(path_in);
    for (const auto& lib : m_libraries)
        if (lib->path == path) return {};  // already loaded
    auto lib = std::make_unique<Library>();
    lib->path = path;
    lib->handle = openLibrary(path);
    lib->info = checkedInfo(path, lib->handle);
    const OptionalEntries entries = optionalEntries(lib->handle, *lib->info);
    std::vector<ModelFactory> added;
    for (int32_t i = 0; i < lib->info->model_count; ++i) {
        ContactModel* proto = makePrototype(path, *lib->info, i);
        lib->references.push_back(proto);  // handed back by ~Library if a later check refuses
        ModelFactory f = describeModel(path, *lib->info, i, proto, entries);
        refuseNameClash(path, f.name, m_models, added);
        added.push_back(std::move(f));
    }
    std::vector<std::string> names;
    for (auto& f : added) {
        names.push_back(f.name);
        m_models.push_back(std::move(f));
    }
    m_libraries.push_back(std::move(lib));
    return names;
}

const ModelFactory* PluginRegistry::tryFind(const std::string& name) const {
    const std::string key = lower(name);
    for (const auto& f : m_models)
        if (lower(f.name) == key) return &f;
    return nullptr;
}

const ModelFactory& PluginRegistry::find(const std::string& name) {
    if (const ModelFactory* f = tryFind(name)) return *f;
    const std::string file = "libtalus_" + lower(name) + ".so";
    for (const auto& dir : m_dirs) {
        const std::string path = dir + "/" + file;
        if (fileExists(path)) {
            load(path);
            if (const ModelFactory* f = tryFind(name)) return *f;
        }
    }
    // The models that can be loaded: the loaded ones and every libtalus_<name>.so on the search
    // path. A name close to one of them is a typo, and the plugin-path advice would mislead.
    std::vector<std::string> loadable = modelNames();
    for (const auto& dir : m_dirs) {
        DIR* d = ::opendir(dir.c_str());
        if (!d) continue;
        while (const dirent* e = ::readdir(d)) {
            const std::string f = e->d_name;
            if (f.size() > 12 && f.compare(0, 9, "libtalus_") == 0 &&
                f.compare(f.size() - 3, 3, ".so") == 0) {
                const std::string stem = f.substr(9, f.size() - 12);
                bool have = false;
                for (const auto& n : loadable) have = have || lower(n) == stem;
                if (!have) loadable.push_back(stem);
            }
        }
        ::closedir(d);
    }
    std::sort(loadable.begin(), loadable.end(),
              [](const std::string& a, const std::string& b) { return lower(a) < lower(b); });
    std::string available;
    for (const auto& n : loadable) available += (available.empty() ? "" : ", ") + n;
    if (available.empty()) available = "none";
    const std::string hint = didYouMean(name, loadable);
    if (!hint.empty())
        throw PluginError("unknown contact model '" + name + "'" + hint +
                          " (models that can be loaded: " + available + ")");
    std::string known;
    for (const auto& n : modelNames()) known += (known.empty() ? "" : ", ") + n;
    std::string dirs;
    for (const auto& d : m_dirs) dirs += (dirs.empty() ? "" : ":") + d;
    throw PluginError("unknown contact model '" + name +
                      "' (models that can be loaded: " + available +
                      "; loaded: " + (known.empty() ? std::string("none") : known) + "; searched " +
                      file + " in " + (dirs.empty() ? std::string("no directories") : dirs) +
                      "; for a model of your own, set TALUS_PLUGIN_PATH or call "
                      "talus.load_plugin)");
}

std::vector<std::string> PluginRegistry::modelNames() const {
    std::vector<std::string> names;
    for (const auto& f : m_models) names.push_back(f.name);
    return names;
}

void PluginRegistry::PrototypeDeleter::operator()(ContactModel* p) const {
    if (p && info) info->destroy_prototype(p);
}

PluginRegistry::PrototypePtr PluginRegistry::createPrototype(const ModelFactory& f) const {
    ContactModel* p = f.info->create_prototype(f.index);
    if (!p) throw PluginError("contact model '" + f.name + "': create_prototype returned null");
    return PrototypePtr(p, PrototypeDeleter{f.info});
}

}  // namespace talus
