#include "vaw/kept_results.hpp"

#include <dlfcn.h>
#include <elf.h>
#include <link.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <system_error>
#include <vector>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/hash.hpp"


namespace vaw {

namespace {

constexpr const char* kMagic = "vaw-kept 1";
constexpr const char* kSuffix = ".vawkept";

// A writer killed between creating and renaming its temporary file leaves ".NAME.XXXXXX.tmp"; one older
// than an hour is no writer's any more.
bool strayTemporary(const std::filesystem::directory_entry& e) {
  const std::string name = e.path().filename().string();
  if (name.size() < 5 || name.front() != '.' || name.substr(name.size() - 4) != ".tmp") return false;
  std::error_code ec;
  const auto written = e.last_write_time(ec);
  return !ec && std::filesystem::file_time_type::clock::now() - written > std::chrono::hours(1);
}

}  // namespace

KeptResults::KeptResults(std::filesystem::path dir, std::uint64_t limitBytes) : dir_(std::move(dir)), limit_(limitBytes) {}

std::optional<KeptResults> KeptResults::under(const std::filesystem::path& root, double limitMB, const std::string& name) {
  if (root.empty() || !(limitMB > 0.0)) return std::nullopt;
  return KeptResults(root / name, static_cast<std::uint64_t>(limitMB * 1048576.0));
}

std::filesystem::path KeptResults::entry(const std::string& key) const { return dir_ / (key + kSuffix); }

std::optional<std::vector<std::uint8_t>> KeptResults::find(const std::string& key) const {
  const std::filesystem::path path = entry(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string magic, keyLine, payloadLine;
  std::getline(in, magic);
  std::getline(in, keyLine);
  std::getline(in, payloadLine);
  const bool headerRead = static_cast<bool>(in);
  std::vector<std::uint8_t> payload(std::istreambuf_iterator<char>(in), {});
  std::uint64_t length = 0;
  char hash[17] = {};
  const bool intact = headerRead && magic == kMagic && keyLine == "key " + key &&
                      std::sscanf(payloadLine.c_str(), "payload %" SCNu64 " %16s", &length, hash) == 2 &&
                      length == payload.size() && hashText(fnv1a(payload.data(), payload.size())) == hash;
  std::error_code ec;
  if (!intact) {
    std::filesystem::remove(path, ec);
    return std::nullopt;
  }
  // Used now: the last to go when the folder is trimmed.
  std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now(), ec);
  return payload;
}

void KeptResults::store(const std::string& key, std::span<const std::uint8_t> result) const {
  if (limit_ == 0) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw OutputError("cannot create the folder " + dir_.string() + ": " + ec.message());
  AtomicFile out(entry(key));
  std::ostringstream header;
  header << kMagic << "\nkey " << key << "\npayload " << result.size() << ' ' << hashText(fnv1a(result.data(), result.size())) << '\n';
  out.write(header.str());
  out.write(std::string_view(reinterpret_cast<const char*>(result.data()), result.size()));
  out.commit();
  trim();
}

void KeptResults::remove(const std::string& key) const {
  std::error_code ec;
  std::filesystem::remove(entry(key), ec);
}

void KeptResults::trim() const {
  struct Entry {
    std::filesystem::path path;
    std::filesystem::file_time_type used;
    std::uintmax_t size;
  };
  std::vector<Entry> entries;
  std::uintmax_t total = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir_, ec)) {
    std::error_code one;
    if (strayTemporary(e)) {
      std::filesystem::remove(e.path(), one);
      continue;
    }
    if (e.path().extension() != kSuffix || !e.is_regular_file(one)) continue;
    Entry x{e.path(), e.last_write_time(one), e.file_size(one)};
    if (one) continue;
    total += x.size;
    entries.push_back(std::move(x));
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& e : entries) {
    if (total <= limit_) break;
    std::error_code one;
    if (std::filesystem::remove(e.path, one)) total -= e.size;
  }
}

namespace {

// The GNU build-id note (the linker's --build-id, Debian's default) among the notes in [p, end), hashed; 0
// when there is none.
std::uint64_t buildIdNote(const unsigned char* p, const unsigned char* end) {
  const auto aligned = [](std::size_t n) { return (n + 3) & ~std::size_t{3}; };
  while (p + sizeof(ElfW(Nhdr)) <= end) {
    ElfW(Nhdr) note;
    std::memcpy(&note, p, sizeof note);
    const unsigned char* name = p + sizeof note;
    const unsigned char* desc = name + aligned(note.n_namesz);
    if (desc + note.n_descsz > end) return 0;
    if (note.n_type == NT_GNU_BUILD_ID && note.n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0 && note.n_descsz > 0)
      return fnv1a(desc, note.n_descsz);
    p = desc + aligned(note.n_descsz);
  }
  return 0;
}

// A file's size and time stamp, for a build without a build-id.
std::uint64_t sizeAndTime(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) return 0;
  const auto written = std::filesystem::last_write_time(file, ec);
  if (ec) return 0;
  const std::uint64_t h = fnv1a(&size, sizeof size);
  const auto ticks = static_cast<std::int64_t>(written.time_since_epoch().count());
  return fnv1a(&ticks, sizeof ticks, h);
}

}  // namespace

std::uint64_t buildIdentity(const void* code) {
  // The build-id of the loaded object that holds `code`, read from its notes in memory.
  struct Search {
    std::uintptr_t code;
    std::uint64_t id = 0;
    bool found = false;
  } search{reinterpret_cast<std::uintptr_t>(code)};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto& s = *static_cast<Search*>(data);
        bool holds = false;
        for (int i = 0; i < info->dlpi_phnum && !holds; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          const std::uintptr_t from = info->dlpi_addr + ph.p_vaddr;
          holds = ph.p_type == PT_LOAD && s.code >= from && s.code < from + ph.p_memsz;
        }
        if (!holds) return 0;
        s.found = true;
        for (int i = 0; i < info->dlpi_phnum && s.id == 0; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          if (ph.p_type != PT_NOTE) continue;
          const auto* notes = reinterpret_cast<const unsigned char*>(info->dlpi_addr + ph.p_vaddr);
          s.id = buildIdNote(notes, notes + ph.p_memsz);
        }
        return 1;
      },
      &search);
  if (search.id != 0) return search.id;
  Dl_info info{};
  if (dladdr(code, &info) == 0 || info.dli_fname == nullptr) return 0;
  return sizeAndTime(info.dli_fname);
}

std::uint64_t buildIdentity(const std::filesystem::path& program) {
  // The notes of a 64-bit ELF file, read through its program headers.
  std::ifstream in(program, std::ios::binary);
  ElfW(Ehdr) header{};
  if (in.read(reinterpret_cast<char*>(&header), sizeof header) && std::memcmp(header.e_ident, ELFMAG, SELFMAG) == 0 &&
      header.e_ident[EI_CLASS] == ELFCLASS64 && header.e_phentsize == sizeof(ElfW(Phdr))) {
    for (int i = 0; i < header.e_phnum; ++i) {
      ElfW(Phdr) ph{};
      in.seekg(static_cast<std::streamoff>(header.e_phoff + static_cast<std::size_t>(i) * sizeof ph));
      if (!in.read(reinterpret_cast<char*>(&ph), sizeof ph)) break;
      if (ph.p_type != PT_NOTE || ph.p_filesz > (1u << 20)) continue;
      std::vector<unsigned char> notes(ph.p_filesz);
      const auto at = in.tellg();
      in.seekg(static_cast<std::streamoff>(ph.p_offset));
      if (!in.read(reinterpret_cast<char*>(notes.data()), static_cast<std::streamsize>(notes.size()))) break;
      in.seekg(at);
      if (const std::uint64_t id = buildIdNote(notes.data(), notes.data() + notes.size())) return id;
    }
  }
  return sizeAndTime(program);
}

}  // namespace vaw
