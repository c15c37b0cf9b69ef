// The bag half of structure_mutators.h: a walk of the bag's records that notes where each number
// the format states is, then one lie in one of them, or one consistent resize of a message.
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "structure_mutators.h"

namespace dynamap::fuzz {
namespace {

std::uint32_t get32(const std::uint8_t* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
void put32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

/// A 4-byte number the bag states, at byte `at`; `bound`: the bytes of what holds what it counts.
struct Number {
  enum Kind { kLength, kOffset, kSize, kConn, kCount, kPos } kind;
  std::size_t at;
  std::uint64_t bound;
  std::size_t chunk;  // kOffset: the chunk (index into Layout::chunks) it points into
};

struct Chunk {
  std::size_t pos = 0, data = 0, size_at = 0;  // record start, first data byte, its size field
  bool plain = false;                          // compression none: its records are walked
  std::vector<std::uint32_t> starts;           // its records' offsets
  std::vector<std::size_t> message_dlen;       // plain: where each message's data_len is
};

struct Layout {
  std::vector<Number> numbers;
  std::vector<Chunk> chunks;
  std::vector<std::uint32_t> conns;
  std::vector<std::size_t> record_starts;
};

/// Where each header field of a record header at [p, p + len) of the input holds its value; the
/// record's op.
char noteFields(const std::uint8_t* base, std::size_t p, std::size_t len, Layout& l, Chunk* chunk) {
  char op = 0;
  for (std::size_t f = p; f + 4 <= p + len;) {
    const std::uint32_t n = get32(base + f);
    if (n > p + len - f - 4) break;
    const std::string field(reinterpret_cast<const char*>(base + f + 4), n);
    f += 4 + n;
    const auto eq = field.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = field.substr(0, eq), value = field.substr(eq + 1);
    const std::size_t at = f - value.size();
    if (key == "op" && value.size() == 1) op = value[0];
    if (key == "compression" && chunk) chunk->plain = value == "none";
    if (value.size() < 4) continue;
    if (key == "conn") {
      l.numbers.push_back({Number::kConn, at, 0, 0});
      l.conns.push_back(get32(base + at));
    } else if (key == "size" && chunk) {
      chunk->size_at = at;
    } else if (key == "count" || key == "conn_count" || key == "chunk_count") {
      l.numbers.push_back({Number::kCount, at, 0, 0});
    } else if (key == "chunk_pos" || key == "index_pos") {
      l.numbers.push_back({Number::kPos, at, 0, 0});
    }
  }
  return op;
}

/// The records in [begin, end): their lengths, fields, and for a plain chunk its own records.
void walk(const std::uint8_t* d, std::size_t begin, std::size_t end, Layout& l, Chunk* inside) {
  for (std::size_t pos = begin; pos + 8 <= end;) {
    const std::uint32_t hlen = get32(d + pos);
    if (hlen > end - pos - 8) return;
    const std::size_t dpos = pos + 4 + hlen;
    const std::uint32_t dlen = get32(d + dpos);
    if (dlen > end - dpos - 4) return;
    l.numbers.push_back({Number::kLength, pos, end - pos - 4, 0});
    l.numbers.push_back({Number::kLength, dpos, end - dpos - 4, 0});
    Chunk c;
    c.pos = pos;
    c.data = dpos + 4;
    const char op = noteFields(d, pos + 4, hlen, l, inside ? nullptr : &c);
    if (inside) {
      inside->starts.push_back(static_cast<std::uint32_t>(pos - begin));
      if (op == 0x02) inside->message_dlen.push_back(dpos);
    } else {
      l.record_starts.push_back(pos);
      if (op == 0x05) {
        if (c.plain) walk(d, c.data, c.data + dlen, l, &c);
        if (c.size_at) l.numbers.push_back({Number::kSize, c.size_at, dlen, 0});
        l.chunks.push_back(c);
      } else if (op == 0x04 && !l.chunks.empty()) {  // an index record's entries
        for (std::size_t e = dpos + 4 + 8; e + 4 <= dpos + 4 + dlen; e += 12) {
          l.numbers.push_back({Number::kOffset, e, 0, l.chunks.size() - 1});
        }
      }
    }
    pos = dpos + 4 + dlen;
  }
}

template <class T>
const T& pick(const std::vector<T>& v, std::mt19937& rng) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}

/// A value for `n` that lies (or, for offsets and ids, points somewhere else real).
std::uint32_t lie(const Number& n, std::uint32_t v, const Layout& l, std::mt19937& rng) {
  const auto small = static_cast<std::uint32_t>(rng() % 9) + 1;
  const std::uint32_t bound = static_cast<std::uint32_t>(std::min<std::uint64_t>(n.bound, ~0u));
  std::vector<std::uint32_t> options = {
      0xFFFFFFFFu, 0x7FFFFFFFu, v + small, v - small, 0u, static_cast<std::uint32_t>(rng())};
  switch (n.kind) {
    case Number::kLength:
    case Number::kSize:
      options.insert(options.end(), {bound, bound + 1, bound - 1, bound + small, v * 2});
      break;
    case Number::kOffset: {
      const Chunk& c = l.chunks[n.chunk];
      if (!c.starts.empty()) options.insert(options.end(), 4, pick(c.starts, rng));
      break;
    }
    case Number::kConn:
      options.insert(options.end(), 3, pick(l.conns, rng));
      break;
    case Number::kPos:
      if (!l.record_starts.empty()) {
        options.insert(options.end(), 3, static_cast<std::uint32_t>(pick(l.record_starts, rng)));
      }
      break;
    case Number::kCount:
      options.insert(options.end(), {v + 1, v - 1, v * 12});
      break;
  }
  return pick(options, rng);
}

/// A message of a plain chunk grown or shrunk by up to 64 bytes at the end of its data, with its
/// data_len, the chunk's data_len and size, the later index offsets and positions restated.
std::size_t resizeMessage(std::uint8_t* d, std::size_t size, std::size_t max_size, const Layout& l,
                          std::mt19937& rng) {
  std::vector<std::size_t> plain;
  for (std::size_t i = 0; i < l.chunks.size(); ++i) {
    if (l.chunks[i].plain && !l.chunks[i].message_dlen.empty() && l.chunks[i].size_at) {
      plain.push_back(i);
    }
  }
  if (plain.empty()) return 0;
  const std::size_t ci = pick(plain, rng);
  const Chunk& c = l.chunks[ci];
  const std::size_t dlen_at = pick(c.message_dlen, rng);
  const std::uint32_t dlen = get32(d + dlen_at);
  const std::size_t at = dlen_at + 4 + dlen;  // the end of the message's data
  const long room = static_cast<long>(max_size - size);
  const long delta =
      std::uniform_int_distribution<long>(-std::min<long>(dlen, 64), std::min<long>(room, 64))(rng);
  if (delta == 0) return 0;
  const auto shift = [&](std::size_t field) { put32(d + field, get32(d + field) + delta); };
  shift(dlen_at);
  shift(c.data - 4);
  shift(c.size_at);
  const std::uint32_t in_chunk = static_cast<std::uint32_t>(dlen_at - c.data);
  for (const Number& n : l.numbers) {
    if (n.kind == Number::kOffset && n.chunk == ci && get32(d + n.at) > in_chunk) shift(n.at);
    if (n.kind == Number::kPos && get32(d + n.at) >= at) shift(n.at);
  }
  if (delta > 0) {
    std::memmove(d + at + delta, d + at, size - at);
    for (long i = 0; i < delta; ++i) d[at + i] = static_cast<std::uint8_t>(rng());
  } else {
    std::memmove(d + at + delta, d + at, size - at);
  }
  return size + delta;
}

}  // namespace

std::size_t mutateBag(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed) {
  static const char kMagic[] = "#ROSBAG V2.0\n";
  if (size < 13 + 8 || std::memcmp(data, kMagic, 13) != 0) return 0;
  Layout l;
  walk(data, 13, size, l, nullptr);
  if (l.numbers.empty()) return 0;
  std::mt19937 rng(seed);
  if (rng() % 4 == 0) {
    if (const std::size_t n = resizeMessage(data, size, max_size, l, rng)) return n;
  }
  const Number& n = pick(l.numbers, rng);
  put32(data + n.at, lie(n, get32(data + n.at), l, rng));
  return size;
}

}  // namespace dynamap::fuzz
