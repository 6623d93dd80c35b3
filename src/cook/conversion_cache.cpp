#include "cook/conversion_cache.h"

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/output_set.h"
#include "files/regular_file.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMagic = "ahdpack-cache 1\n";
constexpr const char* kExt = ".ahdcache";
constexpr const char* kInputsExt = ".ahdinputs";
constexpr size_t kMaxFiles = 4096;
// An entry is read into memory to be published: one larger is never read (a miss) nor stored (the
// store fails: "not cached"). 2 GiB holds a 16384² set of BC6H planes with mips; a sparse 8 GB
// file in the folder costs a stat, not 8 GB (docs/asset-cook.md "The key and the cache").
constexpr uint64_t kMaxEntryBytes = uint64_t(1) << 31;
// The header: the format, key and count lines and one line per file, each at most 1024 bytes.
constexpr size_t kMaxHeaderBytes = (kMaxFiles + 3) * 1024;

bool is_key(const std::string& key) {
  return key.size() == 64 && std::all_of(key.begin(), key.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

bool plain_name(const std::string& n) {
  return !n.empty() && n.size() <= 255 && n != "." && n != ".." && n.find_first_of("/\\\n\r") == std::string::npos &&
         n.find('\0') == std::string::npos;
}

// One header line from `pos` (without its '\n'); false when there is none within 1024 bytes.
bool next_line(const std::vector<uint8_t>& b, size_t* pos, std::string* line) {
  const size_t end = std::min(b.size(), *pos + 1024);
  for (size_t i = *pos; i < end; ++i)
    if (b[i] == '\n') {
      line->assign(reinterpret_cast<const char*>(b.data()) + *pos, i - *pos);
      *pos = i + 1;
      return true;
    }
  return false;
}

bool parse_u64(const std::string& s, uint64_t* v) {
  if (s.empty() || s.size() > 19) return false;
  uint64_t x = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    x = x * 10 + uint64_t(c - '0');
  }
  *v = x;
  return true;
}

}  // namespace

ConversionCache::ConversionCache(std::string dir, uint64_t max_bytes) : dir_(std::move(dir)), max_bytes_(max_bytes) {}

std::string ConversionCache::entry_path(const std::string& key) const { return utf8_string(fs_path(dir_) / fs_path(key + kExt)); }

std::vector<uint8_t> ConversionCache::encode(const std::string& key, const std::vector<OutputFile>& files) {
  std::string header = std::string(kMagic) + "key " + key + "\nfiles " + std::to_string(files.size()) + "\n";
  for (const OutputFile& f : files) {
    if (!plain_name(f.name)) throw Error("cache: not a plain file name: " + f.name);
    header += "file " + std::to_string(f.bytes.size()) + " " + sha256_hex(f.bytes.data(), f.bytes.size()) + " " + f.name + "\n";
  }
  std::vector<uint8_t> out(header.begin(), header.end());
  for (const OutputFile& f : files) out.insert(out.end(), f.bytes.begin(), f.bytes.end());
  return out;
}

namespace {

struct Item {
  uint64_t size;
  std::string sha, name;
};

// The header of an entry for `key` in b[0, n): its files (sizes, hashes, names) and where the bytes
// begin (*body); false unless well-formed with sizes that add up to `total` − *body exactly.
bool parse_header(const std::string& key, const std::vector<uint8_t>& b, uint64_t total, std::vector<Item>* items,
                  size_t* body) {
  const size_t magic = std::strlen(kMagic);
  if (b.size() < magic || std::memcmp(b.data(), kMagic, magic) != 0) return false;
  size_t pos = magic;
  std::string line;
  if (!next_line(b, &pos, &line) || line != "key " + key) return false;
  uint64_t n = 0;
  if (!next_line(b, &pos, &line) || line.rfind("files ", 0) != 0 || !parse_u64(line.substr(6), &n) || n == 0 ||
      n > kMaxFiles)
    return false;
  uint64_t sum = 0;
  for (uint64_t i = 0; i < n; ++i) {
    if (!next_line(b, &pos, &line) || line.rfind("file ", 0) != 0) return false;
    const size_t s1 = line.find(' ', 5);
    if (s1 == std::string::npos || line.size() < s1 + 1 + 64 + 2 || line[s1 + 65] != ' ') return false;
    Item it;
    if (!parse_u64(line.substr(5, s1 - 5), &it.size)) return false;
    it.sha = line.substr(s1 + 1, 64);
    it.name = line.substr(s1 + 66);
    if (!is_key(it.sha) || !plain_name(it.name) || it.size > kMaxEntryBytes) return false;
    sum += it.size;
    items->push_back(std::move(it));
  }
  *body = pos;
  return total >= pos && sum == total - pos;  // else truncated, or bytes appended
}

}  // namespace

std::optional<std::vector<OutputFile>> ConversionCache::decode(const std::string& key, const std::vector<uint8_t>& b) {
  std::vector<Item> items;
  size_t pos = 0;
  if (!parse_header(key, b, b.size(), &items, &pos)) return std::nullopt;
  std::vector<OutputFile> files;
  for (const Item& it : items) {
    OutputFile f{it.name, std::vector<uint8_t>(b.begin() + std::ptrdiff_t(pos), b.begin() + std::ptrdiff_t(pos + it.size))};
    pos += it.size;
    if (sha256_hex(f.bytes.data(), f.bytes.size()) != it.sha) return std::nullopt;
    files.push_back(std::move(f));
  }
  return files;
}

// Streamed: the header is read first (at most kMaxHeaderBytes) and checked against the entry's
// size from fstat before any file's bytes are allocated; each file is then read into its own buffer
// and hashed. A non-regular file, a symlink, an entry over kMaxEntryBytes: a miss, nothing read.
std::optional<std::vector<OutputFile>> ConversionCache::lookup(const std::string& key) const {
  std::vector<std::string> sha256;
  return lookup_hashed(key, &sha256);
}

std::optional<std::vector<OutputFile>> ConversionCache::lookup_hashed(const std::string& key,
                                                                      std::vector<std::string>* sha256) const {
  sha256->clear();
  if (!is_key(key)) return std::nullopt;
  const std::string path = entry_path(key);
  std::vector<OutputFile> files;
  try {
    RegularFile f(path, kMaxEntryBytes, true);
    std::vector<uint8_t> head(size_t(std::min<uint64_t>(f.size(), kMaxHeaderBytes)));
    f.read(head.data(), head.size());
    std::vector<Item> items;
    size_t pos = 0;
    if (!parse_header(key, head, f.size(), &items, &pos)) return std::nullopt;
    size_t in_head = head.size() - pos;  // file bytes already read with the header
    for (const Item& it : items) {
      OutputFile o{it.name, std::vector<uint8_t>(size_t(it.size))};
      const size_t from_head = size_t(std::min<uint64_t>(in_head, it.size));
      if (from_head) std::memcpy(o.bytes.data(), head.data() + pos, from_head);  // an empty file has no data()
      pos += from_head, in_head -= from_head;
      if (o.bytes.size() > from_head) f.read(o.bytes.data() + from_head, o.bytes.size() - from_head);
      std::string sha = sha256_hex(o.bytes.data(), o.bytes.size());
      if (sha != it.sha) {
        sha256->clear();
        return std::nullopt;
      }
      sha256->push_back(std::move(sha));
      files.push_back(std::move(o));
    }
  } catch (const Error&) {
    sha256->clear();
    return std::nullopt;  // missing, removed by another process's eviction meanwhile, too large: a miss
  }
  std::error_code ec;
  fs::last_write_time(fs_path(path), fs::file_time_type::clock::now(), ec);  // LRU: recently used
  return files;
}

CacheStats ConversionCache::store(const std::string& key, const std::vector<OutputFile>& files) const {
  if (!is_key(key)) throw Error("cache: not a key: " + key);
  const std::string path = entry_path(key);
  std::error_code ec;
  fs::create_directories(fs_path(dir_), ec);
  if (ec) throw file_error(dir_, "cannot create the cache folder (" + ec.message() + ")");
  uint64_t total = 0;
  for (const OutputFile& f : files) total += f.bytes.size();
  if (total > kMaxEntryBytes)
    throw file_error(path, "the set is " + std::to_string(total) + " bytes, over the cache's bound of " +
                               std::to_string(kMaxEntryBytes) + " per entry");
  write_file_atomic(path, encode(key, files));

  // Eviction: least recently used first. Races with other processes are harmless: a file another
  // one removed first is skipped, a reader that opened an entry keeps reading it (POSIX unlink).
  CacheStats st;
  struct Entry {
    fs::path path;
    fs::file_time_type mtime;
    uint64_t bytes;
  };
  std::vector<Entry> entries;
  const auto now = fs::file_time_type::clock::now();
  for (const auto& e : fs::directory_iterator(fs_path(dir_), ec)) {
    std::error_code e2;
    if (!e.is_regular_file(e2)) continue;
    const std::string name = utf8_string(e.path().filename());
    const auto mtime = e.last_write_time(e2);
    if (e2) continue;
    if (is_temporary_name(name)) {
      if (now - mtime > std::chrono::hours(1)) fs::remove(e.path(), e2);
      continue;
    }
    if (e.path().extension() != kExt && e.path().extension() != kInputsExt) continue;
    const uint64_t bytes = e.file_size(e2);
    if (e2) continue;
    entries.push_back({e.path(), mtime, bytes});
    st.bytes += bytes;
  }
  st.entries = entries.size();
  if (max_bytes_ == 0 || st.bytes <= max_bytes_) return st;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.mtime != b.mtime ? a.mtime < b.mtime : a.path < b.path;
  });
  for (const Entry& e : entries) {
    if (st.bytes <= max_bytes_) break;
    if (e.path == fs_path(path)) continue;
    std::error_code e2;
    if (fs::remove(e.path, e2)) ++st.evicted;
    st.bytes -= e.bytes, --st.entries;
  }
  return st;
}

std::optional<InputsRecord> ConversionCache::lookup_inputs(const std::string& command_key) const {
  if (!is_key(command_key)) return std::nullopt;
  const std::string path = utf8_string(fs_path(dir_) / fs_path(command_key + kInputsExt));
  std::vector<uint8_t> b;
  try {
    RegularFile f(path, uint64_t(1) << 24, true);  // no FIFO, device or symlink; at most 16 MiB
    b.resize(size_t(f.size()));
    f.read(b.data(), b.size());
  } catch (const Error&) {
    return std::nullopt;
  }
  std::optional<InputsRecord> r = decode_inputs(command_key, b);
  if (!r) return std::nullopt;
  std::error_code ec;
  fs::last_write_time(fs_path(path), fs::file_time_type::clock::now(), ec);
  return r;
}

std::optional<InputsRecord> ConversionCache::decode_inputs(const std::string& command_key,
                                                           const std::vector<uint8_t>& b) {
  const std::string text(b.begin(), b.end());
  const size_t tail = text.rfind("sha256 ");
  if (tail == std::string::npos || text.size() != tail + 7 + 64 + 1 || text.back() != '\n') return std::nullopt;
  if (sha256_hex(b.data(), tail) != text.substr(tail + 7, 64)) return std::nullopt;
  std::istringstream in(text.substr(0, tail));
  std::string line;
  if (!std::getline(in, line) || line != "ahdpack-inputs 1") return std::nullopt;
  if (!std::getline(in, line) || line != "key " + command_key) return std::nullopt;
  InputsRecord r;
  while (std::getline(in, line)) {
    if (line.rfind("opt ", 0) == 0) r.options_text += line.substr(4) + "\n";
    else if (line.rfind("source ", 0) == 0) r.source = line.substr(7);
    else if (line.rfind("file ", 0) == 0) r.files.push_back(line.substr(5));
    else if (line.rfind("probe ", 0) == 0) {
      // The type is std::filesystem::file_type's value: not_found is -1 (an absent file's probe,
      // which every baker set and Godot project has; refused here, it made every such record a miss).
      const size_t sp = line.find(' ', 6);
      const size_t digits = line.size() > 6 && line[6] == '-' ? 7 : 6;
      if (sp == std::string::npos || sp == digits || sp - digits > 3) return std::nullopt;
      InputProbe p;
      for (size_t i = digits; i < sp; ++i) {
        if (line[i] < '0' || line[i] > '9') return std::nullopt;
        p.type = p.type * 10 + (line[i] - '0');
      }
      if (digits == 7) p.type = -p.type;
      p.path = line.substr(sp + 1);
      r.probes.push_back(std::move(p));
    } else {
      return std::nullopt;
    }
  }
  if (r.options_text.empty()) return std::nullopt;
  return r;
}

std::optional<std::string> ConversionCache::encode_inputs(const std::string& command_key, const InputsRecord& r) {
  if (!is_key(command_key)) throw Error("cache: not a key: " + command_key);
  const auto one_line = [](const std::string& s) { return s.find_first_of("\n\r") == std::string::npos; };
  for (const std::string& f : r.files)
    if (!one_line(f)) return std::nullopt;
  for (const InputProbe& p : r.probes)
    if (!one_line(p.path)) return std::nullopt;
  std::string t = "ahdpack-inputs 1\nkey " + command_key + "\n";
  std::string source = r.source;
  for (char& c : source)
    if (c == '\n' || c == '\r') c = ' ';
  t += "source " + source + "\n";
  std::istringstream opts(r.options_text);
  std::string line;
  while (std::getline(opts, line)) t += "opt " + line + "\n";
  for (const std::string& f : r.files) t += "file " + f + "\n";
  for (const InputProbe& p : r.probes) t += "probe " + std::to_string(p.type) + " " + p.path + "\n";
  t += "sha256 " + sha256_hex(reinterpret_cast<const uint8_t*>(t.data()), t.size()) + "\n";
  return t;
}

void ConversionCache::store_inputs(const std::string& command_key, const InputsRecord& r) const {
  const std::optional<std::string> t = encode_inputs(command_key, r);
  if (!t) return;
  std::error_code ec;
  fs::create_directories(fs_path(dir_), ec);
  write_file_atomic(utf8_string(fs_path(dir_) / fs_path(command_key + kInputsExt)), *t);
}

uint64_t parse_byte_size(const std::string& text, const std::string& option) {
  std::string digits = text;
  uint64_t mult = 1;
  if (!digits.empty()) {
    const char s = char(std::toupper(static_cast<unsigned char>(digits.back())));
    const int shift = s == 'K' ? 10 : s == 'M' ? 20 : s == 'G' ? 30 : s == 'T' ? 40 : 0;
    if (shift) mult = uint64_t(1) << shift, digits.pop_back();
  }
  uint64_t v = 0;
  if (!parse_u64(digits, &v) || v > (UINT64_MAX >> 40))
    throw Error(option + " must be a byte count with an optional K, M, G or T suffix (got '" + text + "')");
  return v * mult;
}

}  // namespace ahd
