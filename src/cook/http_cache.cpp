// The cache on an HTTP server (`ahdpack convert --cache http://host:port/prefix/`), speaking the
// protocol of Bazel's HTTP remote cache, so the server a team already runs for Bazel (nginx with
// WebDAV PUT, bazel-remote, …) serves ahdpack too (docs/asset-cook.md "A team's cache over HTTP"):
//
//   PUT/GET  PREFIX/cas/<sha256>  a blob, addressed by the SHA-256 of its bytes
//   PUT/GET  PREFIX/ac/<key>      an ActionResult (the protocol buffer of Bazel's remote execution
//                                 API) naming one output file by its digest: the blob of the entry
//
// The blob of a conversion is the folder cache's entry (ConversionCache::encode: a header with each
// file's size and SHA-256, then the files), so a hit is checked exactly as the folder cache checks
// one (ConversionCache::decode: key, names, sizes, every file's SHA-256), after the blob's own
// SHA-256 is checked against the digest the ActionResult names; the cook then checks the manifest
// against the planes. A command's inputs record (ConversionCache::encode_inputs) is kept the same
// way under the command key. The blob is stored before the ActionResult that names it, so a reader
// never finds a result without its blob; two writers of one key write the same bytes.
//
// The client is ours: HTTP/1.1 over POSIX sockets, one connection per request (Connection: close),
// no TLS (https://: a TLS-terminating proxy on the machine, or a trusted network). Every read is
// bounded (headers 64 KiB, an ActionResult 64 KiB, an entry as the folder cache's bound) and every
// wait has a timeout (connect 5 s, then 30 s without progress; `?timeout=S` sets both). A miss, a
// server error or a timeout on a lookup is a miss; a failed store throws (the cook warns once and
// the conversion stands). A server that could not be reached (refused, reset, timed out) is not
// asked again by this process: later lookups miss at once and stores fail at once, saying why.
// POSIX only: on Windows cook/http_cache_win32.cpp says the HTTP cache is not available there.
#ifndef _WIN32
#include <ahd/cook.h>
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <functional>
#include <mutex>
#include <string_view>

#include "containers/sha256.h"
#include "cook/conversion_cache.h"
#include "core/error.h"

namespace ahd {

std::shared_ptr<const CacheBackend> open_http_cache(const std::string& url, uint64_t max_bytes);

namespace {

// The folder cache's bound per entry (cook/conversion_cache.cpp kMaxEntryBytes) and per inputs record.
constexpr uint64_t kMaxEntryBytes = uint64_t(1) << 31;
constexpr uint64_t kMaxInputsBytes = uint64_t(1) << 24;
constexpr size_t kMaxHeaderBytes = 64 << 10;
constexpr size_t kMaxActionResultBytes = 64 << 10;
// The name of the one output file an ActionResult of ours lists, per kind of blob.
constexpr const char* kEntryName = "ahdpack.ahdcache";
constexpr const char* kInputsName = "ahdpack.ahdinputs";

bool is_hex64(const std::string& s) {
  return s.size() == 64 &&
         std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// A failure to talk to the server at all (refused, reset, timed out, closed early): the server is
// then treated as gone for the rest of the process.
struct TransportError : Error {
  using Error::Error;
};

struct Url {
  std::string base;  // "http://host:port/prefix/" (for messages)
  std::string host;  // as given, without brackets
  std::string port = "80";
  std::string authority;  // the Host header
  std::string path;       // "/prefix/"
  int timeout_ms = 30000, connect_timeout_ms = 5000;
};

Url parse_url(const std::string& url) {
  const auto bad = [&](const std::string& why) { return Error(url + ": not a usable cache URL (" + why + ")"); };
  Url u;
  const std::string scheme = "http://";
  if (url.rfind(scheme, 0) != 0) throw bad("only http:// is built in: put a TLS proxy on this machine for https");
  std::string rest = url.substr(scheme.size());
  const size_t q = rest.find('?');
  std::string query;
  if (q != std::string::npos) query = rest.substr(q + 1), rest.resize(q);
  if (rest.find('#') != std::string::npos) throw bad("a fragment");
  const size_t slash = rest.find('/');
  u.authority = rest.substr(0, slash);
  u.path = slash == std::string::npos ? "/" : rest.substr(slash);
  if (u.path.back() != '/') u.path += '/';
  for (char c : u.path)
    if (c <= ' ' || c == 127 || c == '%' || c == '\\') throw bad("the path must be plain: letters, digits, -._~/");
  if (u.authority.empty()) throw bad("no host");
  if (u.authority.find('@') != std::string::npos) throw bad("credentials in the URL are not supported");
  std::string hostport = u.authority;
  if (hostport[0] == '[') {  // [IPv6]:port
    const size_t close = hostport.find(']');
    if (close == std::string::npos) throw bad("an unclosed '['");
    u.host = hostport.substr(1, close - 1);
    if (close + 1 < hostport.size()) {
      if (hostport[close + 1] != ':') throw bad("junk after ']'");
      u.port = hostport.substr(close + 2);
    }
  } else {
    const size_t colon = hostport.rfind(':');
    u.host = hostport.substr(0, colon);
    if (colon != std::string::npos) u.port = hostport.substr(colon + 1);
  }
  if (u.host.empty() || u.port.empty() || u.port.size() > 5 ||
      !std::all_of(u.port.begin(), u.port.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      std::stoi(u.port) == 0 || std::stoi(u.port) > 65535)
    throw bad("host:port expected");
  for (char c : u.host)
    if (c <= ' ' || c == 127) throw bad("a control character in the host");
  if (!query.empty()) {  // ?timeout=SECONDS (1–3600): both the connect and the I/O timeout
    const std::string k = "timeout=";
    const std::string v = query.rfind(k, 0) == 0 ? query.substr(k.size()) : "";
    if (v.empty() || v.size() > 4 || !std::all_of(v.begin(), v.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
        std::stoi(v) < 1 || std::stoi(v) > 3600)
      throw bad("the only query is ?timeout=SECONDS, 1 to 3600");
    u.timeout_ms = u.connect_timeout_ms = std::stoi(v) * 1000;
  }
  u.base = "http://" + u.authority + u.path;
  return u;
}

class Socket {
 public:
  explicit Socket(int fd) : fd_(fd) {}
  ~Socket() {
    if (fd_ >= 0) ::close(fd_);
  }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
  int fd() const { return fd_; }

 private:
  int fd_;
};

std::string errno_text(int e) { return std::strerror(e); }

int connect_to(const Url& u) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const int g = getaddrinfo(u.host.c_str(), u.port.c_str(), &hints, &res);
  if (g != 0) throw TransportError(u.authority + ": cannot resolve the host (" + gai_strerror(g) + ")");
  std::string why = "no address";
  int fd = -1;
  for (addrinfo* a = res; a && fd < 0; a = a->ai_next) {
    const int s = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
    if (s < 0) {
      why = errno_text(errno);
      continue;
    }
    int r = ::connect(s, a->ai_addr, a->ai_addrlen);
    if (r != 0 && errno == EINPROGRESS) {
      pollfd p{s, POLLOUT, 0};
      do r = ::poll(&p, 1, u.connect_timeout_ms);
      while (r < 0 && errno == EINTR);
      if (r == 0) {
        why = "no answer within " + std::to_string(u.connect_timeout_ms / 1000) + " s";
        ::close(s);
        continue;
      }
      int err = 0;
      socklen_t len = sizeof(err);
      if (r < 0) err = errno;
      else if (::getsockopt(s, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
      r = err ? -1 : 0;
      errno = err;
    }
    if (r != 0) {
      why = errno_text(errno);
      ::close(s);
      continue;
    }
    fd = s;
  }
  freeaddrinfo(res);
  if (fd < 0) throw TransportError(u.authority + ": cannot connect (" + why + ")");
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  timeval tv{u.timeout_ms / 1000, (u.timeout_ms % 1000) * 1000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof(tv));
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return fd;
}

void send_all(int fd, const Url& u, const uint8_t* p, size_t n) {
  while (n) {
    const ssize_t k = ::send(fd, p, std::min<size_t>(n, size_t(1) << 20), MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
      throw TransportError("the server took nothing for " + std::to_string(u.timeout_ms / 1000) + " s");
    if (k <= 0) throw TransportError("the connection broke while sending (" + errno_text(errno) + ")");
    p += k, n -= size_t(k);
  }
}

// Up to n bytes; 0 at the end of the stream.
size_t recv_some(int fd, const Url& u, uint8_t* p, size_t n) {
  for (;;) {
    const ssize_t k = ::recv(fd, p, n, 0);
    if (k >= 0) return size_t(k);
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK)
      throw TransportError("the server sent nothing for " + std::to_string(u.timeout_ms / 1000) + " s");
    throw TransportError("the connection broke while receiving (" + errno_text(errno) + ")");
  }
}

struct Response {
  int status = 0;
  bool too_large = false;  // a 200 whose body is over the bound: not read
  std::vector<uint8_t> body;
};

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// One request on its own connection. The body of a GET's 200 is read when at most `max_body`
// bytes (exactly Content-Length of them; chunked bodies are refused); no other answer's body is.
// Throws TransportError when the exchange does not complete, Error for a malformed answer.
Response exchange(const Url& u, const std::string& method, const std::string& target, const std::vector<uint8_t>* body,
                  uint64_t max_body) {
  Socket s(connect_to(u));
  std::string head =
      method + " " + target + " HTTP/1.1\r\nHost: " + u.authority + "\r\nUser-Agent: ahdpack\r\nConnection: close\r\n";
  if (body)
    head += "Content-Type: application/octet-stream\r\nContent-Length: " + std::to_string(body->size()) + "\r\n";
  head += "\r\n";
  send_all(s.fd(), u, reinterpret_cast<const uint8_t*>(head.data()), head.size());
  if (body) send_all(s.fd(), u, body->data(), body->size());

  std::vector<uint8_t> buf;
  size_t end = std::string::npos;
  while (end == std::string::npos) {
    if (buf.size() >= kMaxHeaderBytes) throw Error("the answer's header is over 64 KiB");
    const size_t at = buf.size();
    buf.resize(at + 4096);
    const size_t k = recv_some(s.fd(), u, buf.data() + at, buf.size() - at);
    buf.resize(at + k);
    if (k == 0) throw TransportError("the server closed the connection without an answer");
    const std::string_view v(reinterpret_cast<const char*>(buf.data()), buf.size());
    end = v.find("\r\n\r\n");
  }
  const std::string header(reinterpret_cast<const char*>(buf.data()), end);
  Response r;
  if (header.size() < 12 || header.rfind("HTTP/1.", 0) != 0 || header[8] != ' ' ||
      !std::all_of(header.begin() + 9, header.begin() + 12, [](char c) { return c >= '0' && c <= '9'; }))
    throw Error("not an HTTP/1.x answer");
  r.status = std::stoi(header.substr(9, 3));
  if (r.status != 200 || method != "GET") return r;  // a PUT's answer body is not needed
  int64_t length = -1;
  size_t pos = header.find("\r\n");
  while (pos != std::string::npos && pos < header.size()) {
    const size_t next = header.find("\r\n", pos + 2);
    const std::string line = header.substr(pos + 2, next == std::string::npos ? std::string::npos : next - pos - 2);
    pos = next;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string name = lower(line.substr(0, colon));
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    value.erase(value.find_last_not_of(" \t") + 1);
    if (name == "transfer-encoding" && lower(value) != "identity") throw Error("a chunked answer (not supported)");
    if (name == "content-length") {
      if (value.empty() || value.size() > 18 ||
          !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw Error("a malformed Content-Length");
      length = std::stoll(value);
    }
  }
  if (length < 0) throw Error("an answer without Content-Length (not supported)");
  if (uint64_t(length) > max_body) {
    r.too_large = true;
    return r;
  }
  r.body.assign(buf.begin() + std::ptrdiff_t(end + 4), buf.end());
  if (r.body.size() > uint64_t(length)) throw Error("more bytes than Content-Length");
  size_t have = r.body.size();
  r.body.resize(size_t(length));
  while (have < r.body.size()) {
    const size_t k = recv_some(s.fd(), u, r.body.data() + have, r.body.size() - have);
    if (k == 0)
      throw TransportError("the answer ended after " + std::to_string(have) + " of " + std::to_string(length) +
                           " bytes");
    have += k;
  }
  return r;
}

// ---- The ActionResult (build/bazel/remote/execution/v2/remote_execution.proto): the few fields
// we write and read, in protocol-buffer wire format. ActionResult.output_files = 2 (OutputFile:
// path = 1, digest = 2); Digest: hash = 1 (hex), size_bytes = 2.

void put_varint(std::string* o, uint64_t v) {
  while (v >= 0x80) o->push_back(char(0x80 | (v & 0x7f))), v >>= 7;
  o->push_back(char(v));
}
void put_bytes(std::string* o, int field, const std::string& b) {
  put_varint(o, uint64_t(field) << 3 | 2);
  put_varint(o, b.size());
  *o += b;
}

std::string action_result(const std::string& name, const std::string& sha, uint64_t size) {
  std::string digest, file, result;
  put_bytes(&digest, 1, sha);
  put_varint(&digest, 2 << 3 | 0);
  put_varint(&digest, size);
  put_bytes(&file, 1, name);
  put_bytes(&file, 2, digest);
  put_bytes(&result, 2, file);
  return result;
}

// Walks the fields of one message in [p, e): f(field, wire type, varint value, bytes) for each;
// false for anything malformed (a varint over 10 bytes, a length past the end, a group).
template <class F>
bool walk_fields(const uint8_t* p, const uint8_t* e, F&& f) {
  const auto varint = [&](uint64_t* v) {
    *v = 0;
    for (int shift = 0; shift < 70; shift += 7) {
      if (p == e) return false;
      const uint8_t b = *p++;
      *v |= uint64_t(b & 0x7f) << shift;
      if (!(b & 0x80)) return true;
    }
    return false;
  };
  while (p < e) {
    uint64_t tag = 0, v = 0;
    if (!varint(&tag)) return false;
    const int wire = int(tag & 7);
    const uint64_t field = tag >> 3;
    std::string_view bytes;
    if (wire == 0) {
      if (!varint(&v)) return false;
    } else if (wire == 1 || wire == 5) {
      const size_t n = wire == 1 ? 8 : 4;
      if (size_t(e - p) < n) return false;
      p += n;
    } else if (wire == 2) {
      if (!varint(&v) || v > uint64_t(e - p)) return false;
      bytes = std::string_view(reinterpret_cast<const char*>(p), size_t(v));
      p += v;
    } else {
      return false;
    }
    f(field, wire, v, bytes);
  }
  return true;
}

bool walk_fields(std::string_view b, const std::function<void(uint64_t, int, uint64_t, std::string_view)>& f) {
  const auto* p = reinterpret_cast<const uint8_t*>(b.data());
  return walk_fields(p, p + b.size(), f);
}

// The digest of the output file `name` in an ActionResult, or false.
bool find_output(const std::vector<uint8_t>& ar, const std::string& name, std::string* sha, uint64_t* size) {
  bool found = false, ok = true;
  const bool walked =
      walk_fields(std::string_view(reinterpret_cast<const char*>(ar.data()), ar.size()),
                  [&](uint64_t field, int wire, uint64_t, std::string_view file) {
                    if (field != 2 || wire != 2) return;
                    std::string path, hash;
                    uint64_t bytes = 0;
                    bool has_size = false;
                    ok = ok && walk_fields(file, [&](uint64_t ff, int fw, uint64_t, std::string_view fb) {
                           if (ff == 1 && fw == 2) path = std::string(fb);
                           if (ff == 2 && fw == 2)
                             ok = ok && walk_fields(fb, [&](uint64_t df, int dw, uint64_t dv, std::string_view db) {
                                    if (df == 1 && dw == 2) hash = std::string(db);
                                    if (df == 2 && dw == 0) bytes = dv, has_size = true;
                                  });
                         });
                    if (path == name && is_hex64(hash) && (has_size || bytes == 0))
                      *sha = hash, *size = bytes, found = true;
                  });
  return walked && ok && found;
}

class HttpCache : public CacheBackend {
 public:
  explicit HttpCache(Url url) : url_(std::move(url)) {}

  std::optional<std::vector<OutputFile>> lookup(const std::string& key) const override {
    if (!is_hex64(key)) return std::nullopt;
    std::optional<std::vector<uint8_t>> b = get_blob(key, kEntryName, kMaxEntryBytes);
    if (!b) return std::nullopt;
    return ConversionCache::decode(key, *b);
  }

  CacheStats store(const std::string& key, const std::vector<OutputFile>& files) const override {
    if (!is_hex64(key)) throw Error("cache: not a key: " + key);
    uint64_t total = 0;
    for (const OutputFile& f : files) total += f.bytes.size();
    if (total > kMaxEntryBytes)
      throw file_error(entry_path(key), "the set is " + std::to_string(total) + " bytes, over the cache's bound of " +
                                            std::to_string(kMaxEntryBytes) + " per entry");
    put_blob(key, kEntryName, ConversionCache::encode(key, files));
    return {};  // the server keeps (and bounds) its own size
  }

  std::optional<InputsRecord> lookup_inputs(const std::string& command_key) const override {
    if (!is_hex64(command_key)) return std::nullopt;
    std::optional<std::vector<uint8_t>> b = get_blob(command_key, kInputsName, kMaxInputsBytes);
    if (!b) return std::nullopt;
    return ConversionCache::decode_inputs(command_key, *b);
  }

  // After a failed store the cook calls this too: a server already found gone was said once (by the
  // store's warning), so the record, which only saves the next run a read, is then left out quietly.
  void store_inputs(const std::string& command_key, const InputsRecord& record) const override {
    const std::optional<std::string> t = ConversionCache::encode_inputs(command_key, record);
    if (!t || gone_.load()) return;
    put_blob(command_key, kInputsName, std::vector<uint8_t>(t->begin(), t->end()));
  }

  std::string entry_path(const std::string& key) const override { return url_.base + "ac/" + key; }

 private:
  // The blob the ActionResult under ac/<key> names as `name`, checked against its digest; nullopt
  // for a miss, anything malformed, or a server that does not answer.
  std::optional<std::vector<uint8_t>> get_blob(const std::string& key, const char* name, uint64_t max_bytes) const {
    if (gone_.load()) return std::nullopt;
    try {
      const Response ar = exchange(url_, "GET", url_.path + "ac/" + key, nullptr, kMaxActionResultBytes);
      if (ar.status != 200 || ar.too_large) return std::nullopt;
      std::string sha;
      uint64_t size = 0;
      if (!find_output(ar.body, name, &sha, &size) || size > max_bytes) return std::nullopt;
      Response blob = exchange(url_, "GET", url_.path + "cas/" + sha, nullptr, size);
      if (blob.status != 200 || blob.too_large || blob.body.size() != size) return std::nullopt;
      if (sha256_hex(blob.body.data(), blob.body.size()) != sha) return std::nullopt;
      return std::move(blob.body);
    } catch (const TransportError& e) {
      mark_gone(e.what());
    } catch (const Error&) {}
    return std::nullopt;
  }

  // The blob to cas/<sha256>, then the ActionResult naming it to ac/<key>. Throws ahd::Error naming
  // the entry.
  void put_blob(const std::string& key, const char* name, const std::vector<uint8_t>& bytes) const {
    const std::string where = entry_path(key);
    if (gone_.load()) {
      const std::lock_guard<std::mutex> l(m_);
      throw file_error(where, "not stored: the cache server did not answer earlier in this run (" + gone_why_ + ")");
    }
    const std::string sha = sha256_hex(bytes.data(), bytes.size());
    const std::string ar = action_result(name, sha, bytes.size());
    const std::vector<uint8_t> ar_bytes(ar.begin(), ar.end());
    try {
      for (const auto& [target, body] :
           {std::pair{url_.path + "cas/" + sha, &bytes}, std::pair{url_.path + "ac/" + key, &ar_bytes}}) {
        const Response r = exchange(url_, "PUT", target, body, 0);
        if (r.status != 200 && r.status != 201 && r.status != 204)
          throw Error("PUT http://" + url_.authority + target + ": the server answered " + std::to_string(r.status));
      }
    } catch (const TransportError& e) {
      mark_gone(e.what());
      throw file_error(where, std::string("not stored: ") + e.what());
    } catch (const Error& e) {
      throw file_error(where, std::string("not stored: ") + e.what());
    }
  }

  void mark_gone(const std::string& why) const {
    const std::lock_guard<std::mutex> l(m_);
    if (!gone_.exchange(true)) gone_why_ = why;
  }

  Url url_;
  mutable std::atomic<bool> gone_{false};
  mutable std::mutex m_;
  mutable std::string gone_why_;
};

}  // namespace

// `max_bytes` is not used: the server bounds its own size (nginx: none; bazel-remote: --max_size).
std::shared_ptr<const CacheBackend> open_http_cache(const std::string& url, uint64_t /*max_bytes*/) {
  return std::make_shared<const HttpCache>(parse_url(url));
}

}  // namespace ahd
#endif  // !_WIN32
