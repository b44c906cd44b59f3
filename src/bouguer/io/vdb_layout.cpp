// The layout check of an OpenVDB file before OpenVDB reads it (io/vdb_layout.h). The field order
// follows OpenVDB 10's readers: io::Archive::readHeader, MetaMap::readMeta, GridDescriptor::read,
// math::Transform::read, RootNode/InternalNode/LeafNode::readTopology and readBuffers, and
// io::readCompressedValues with bloscFromStream/unzipFromStream (io/Compression.h).
#include "bouguer/io/vdb_layout.h"

#include <fmt/format.h>

#include <openvdb/Metadata.h>
#include <openvdb/io/Compression.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/StreamCompression.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <functional>
#include <string_view>
#include <vector>

namespace bouguer::vdb_layout {
namespace {

using vdb_module::Result;
using vdb_module::Status;

struct Problem {
  Result result;
};

// Every read of the walk: bounded by the bytes that remain, positions in bytes from the start.
class Cursor {
 public:
  explicit Cursor(const std::string& path) : path_(path), in_(path, std::ios::binary | std::ios::ate) {
    if (!in_) fail("cannot be opened");
    size_ = static_cast<std::uint64_t>(in_.tellg());
    in_.seekg(0);
  }

  template <typename... Args>
  [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
    // Worded as the module's other refusals of a file OpenVDB would fail on (io/vdb_module.cpp).
    throw Problem{{Status::file_problem, fmt::format("{}: OpenVDB cannot read it: {} (a damaged or crafted file)",
                                                     path_, fmt::format(f, std::forward<Args>(args)...))}};
  }

  std::uint64_t pos() const { return pos_; }
  std::uint64_t size() const { return size_; }
  const std::string& path() const { return path_; }

  void need(std::uint64_t bytes, std::string_view what) const {
    if (bytes > size_ - pos_)
      fail("{} at byte {} needs {} bytes, but {} remain", what, pos_, bytes, size_ - pos_);
  }
  void seek(std::uint64_t to) {
    pos_ = to;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(to));
  }
  void skip(std::uint64_t bytes, std::string_view what) {
    need(bytes, what);
    seek(pos_ + bytes);
  }
  std::string bytes(std::uint64_t n, std::string_view what) {
    need(n, what);
    std::string s(static_cast<std::size_t>(n), '\0');
    in_.read(s.data(), static_cast<std::streamsize>(n));
    if (!in_) fail("{} at byte {} cannot be read", what, pos_);
    pos_ += n;
    return s;
  }
  template <typename T>
  T get(std::string_view what) {
    const std::string b = bytes(sizeof(T), what);
    T v;
    std::memcpy(&v, b.data(), sizeof(T));
    return v;
  }
  std::string string(std::string_view what) { return bytes(get<std::uint32_t>(what), what); }
  // The stream at byte `at`, for OpenVDB's own decompression (the walk's position is not moved).
  std::istream& stream_at(std::uint64_t at) {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    return in_;
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0, pos_ = 0;
};

constexpr std::uint32_t kFirstVersion = 222, kLastVersion = 224;  // OpenVDB 3 to 12 write 222-224
constexpr std::uint32_t kZip = 0x1, kActiveMask = 0x2, kBlosc = 0x4;  // io::COMPRESS_*
constexpr std::string_view kFloatTree = "Tree_float_5_4_3", kHalfSuffix = "_HalfFloat";

void header(Cursor& c) {
  c.skip(8, "the magic number");  // checked by the library (io/vdb.cpp)
  const auto version = c.get<std::uint32_t>("the format version");
  if (version < kFirstVersion || version > kLastVersion)
    c.fail("OpenVDB file format {}; Bouguer reads formats {} to {} (OpenVDB 3 and later)", version, kFirstVersion,
           kLastVersion);
  c.skip(8, "the library version");
  if (c.get<std::uint8_t>("the grid-offsets flag") == 0)
    c.fail("written as a stream without grid offsets (io::Stream); Bouguer reads files written by io::File");
  // The UUID as 36 ASCII characters, read by boost's operator>>, which would skip white space.
  const std::uint64_t at = c.pos();
  const std::string uuid = c.bytes(36, "the UUID");
  for (std::size_t i = 0; i < uuid.size(); ++i) {
    const bool hyphen = i == 8 || i == 13 || i == 18 || i == 23;
    const char ch = uuid[i];
    const bool hex = (ch >= '0' && ch <= '9') || (ch >= 'a' && ch <= 'f') || (ch >= 'A' && ch <= 'F');
    if (hyphen ? ch != '-' : !hex) c.fail("its UUID at byte {} is not 36 characters of hex digits and hyphens", at);
  }
}

// One blosc header (blosc.h: nbytes at byte 4, cbytes at byte 12) of a chunk of `chunk` bytes that
// must decompress to `expected` bytes, or with `padded` (points/StreamCompression's bloscCompress,
// which the delayed-load metadata uses) to BLOSC_PAD_BYTES where fewer were compressed.
void blosc_header(Cursor& c, std::uint64_t chunk, std::uint64_t expected, std::string_view what,
                  bool padded = false) {
  c.need(chunk, what);
  if (chunk < 16) c.fail("{} at byte {} is {} bytes, shorter than a blosc header", what, c.pos(), chunk);
  const std::string h = c.bytes(16, what);
  std::uint32_t nbytes = 0, cbytes = 0;
  std::memcpy(&nbytes, h.data() + 4, 4);
  std::memcpy(&cbytes, h.data() + 12, 4);
  constexpr std::uint64_t kPad = openvdb::compression::BLOSC_PAD_BYTES;
  const bool pad_ok = padded && expected < kPad && nbytes == kPad;
  if ((nbytes != expected && !pad_ok) || cbytes != chunk)
    c.fail("{} at byte {}: its blosc header says {} bytes from {}, where the chunk holds {} and its node needs {}",
           what, c.pos() - 16, nbytes, cbytes, chunk, expected);
  c.skip(chunk - 16, what);
}

// io::DelayedLoadMetadata::readValue: a count, a mask (blosc or raw), compressed sizes (blosc, raw or
// absent), exactly `value_bytes` in all. The count is of leaves, each at least 64 bytes of the file.
void delayed_load(Cursor& c, std::uint32_t value_bytes) {
  if (value_bytes == 0) return;
  const std::uint64_t start = c.pos();
  const auto count = c.get<std::uint32_t>("the delayed-load count");
  if (std::uint64_t{count} * 64 > c.size()) c.fail("its delayed-load metadata counts {} leaves", count);
  const auto part = [&](std::uint32_t bytes, std::uint64_t raw, std::string_view what) {
    if (bytes > 0) blosc_header(c, bytes, raw, what, /*padded=*/true);
    else c.skip(raw, what);
  };
  part(c.get<std::uint32_t>("the delayed-load mask size"), count, "the delayed-load mask");
  const auto sizes = c.get<std::uint32_t>("the delayed-load sizes size");
  if (sizes != 0xffffffffu) part(sizes, std::uint64_t{count} * 8, "the delayed-load sizes");
  if (c.pos() - start != value_bytes)
    c.fail("its delayed-load metadata at byte {} states {} bytes but holds {}", start, value_bytes, c.pos() - start);
}

// MetaMap::readMeta. A registered type other than a string reads its own size, whatever the size
// field says, so the two must agree for the walk to stay where OpenVDB is.
void metadata(Cursor& c, std::string_view what) {
  const auto count = c.get<std::uint32_t>(what);
  c.need(std::uint64_t{count} * 12, what);  // each entry: two string lengths and a size
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string name = c.string(what);
    const std::string type = c.string(what);
    const auto value_bytes = c.get<std::uint32_t>(what);
    if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
      delayed_load(c, value_bytes);
    } else if (type == openvdb::StringMetadata::staticTypeName() || !openvdb::Metadata::isRegisteredType(type)) {
      c.skip(value_bytes, what);
    } else {
      const std::uint32_t size = openvdb::Metadata::createMetadata(type)->size();
      if (value_bytes != size) c.fail("{}: '{}' of type {} states {} bytes, not {}", what, name, type, value_bytes, size);
      c.skip(size, what);
    }
  }
}

struct Descriptor {
  std::string name, type, parent;
  bool half = false;
  std::uint64_t grid_pos = 0, end_pos = 0;
};

// The grid descriptors after the file's metadata (File::open): each grid's data lies between its
// descriptor and the next, whose position the descriptor's end position gives.
std::vector<Descriptor> descriptors(Cursor& c) {
  const auto count = c.get<std::int32_t>("the grid count");
  if (count < 0) c.fail("its grid count is {}", count);
  c.need(std::uint64_t(count) * 36, "the grid descriptors");
  std::vector<Descriptor> out;
  for (std::int32_t i = 0; i < count; ++i) {
    Descriptor d;
    d.name = c.string("a grid name");
    d.type = c.string("a grid type");
    d.parent = c.string("an instance parent's name");
    if (d.type.ends_with(kHalfSuffix)) {
      d.half = true;
      d.type.resize(d.type.size() - kHalfSuffix.size());
    }
    const auto grid_pos = c.get<std::int64_t>("a grid position");
    const auto block_pos = c.get<std::int64_t>("a grid position");
    const auto end_pos = c.get<std::int64_t>("a grid position");
    // An instance (Archive::writeGridInstance) shares its parent's tree and never sets its block
    // position, which stays 0.
    const bool instance_block = !d.parent.empty() && block_pos == 0;
    if (grid_pos != static_cast<std::int64_t>(c.pos()) ||
        (!instance_block && (block_pos < grid_pos || end_pos < block_pos)) || end_pos < grid_pos ||
        static_cast<std::uint64_t>(end_pos) > c.size())
      c.fail("grid descriptor {} at byte {} places its grid at bytes {}, {}, {} in a file of {}", i, c.pos() - 24,
             grid_pos, block_pos, end_pos, c.size());
    d.grid_pos = static_cast<std::uint64_t>(grid_pos);
    d.end_pos = static_cast<std::uint64_t>(end_pos);
    out.push_back(std::move(d));
    c.seek(static_cast<std::uint64_t>(end_pos));
  }
  return out;
}

std::string shown(const std::string& unique_name) {  // GridDescriptor's suffix "\x1e[n]" off
  return unique_name.substr(0, unique_name.find('\x1e'));
}

// math::Transform::read: the map's type name, then its matrices and vectors (math/Maps.h).
void transform(Cursor& c, const Descriptor& d) {
  const std::string type = c.string("a map type");
  static constexpr std::array<std::pair<std::string_view, std::uint64_t>, 7> kMapBytes{{
      {"AffineMap", 128}, {"UnitaryMap", 128}, {"ScaleMap", 120}, {"UniformScaleMap", 120},
      {"TranslationMap", 24}, {"ScaleTranslateMap", 144}, {"UniformScaleTranslateMap", 144}}};
  if (type == "NonlinearFrustumMap")
    throw Problem{{Status::grid_problem, fmt::format("{}: grid '{}': its index-to-world map ({}) is not linear",
                                                     c.path(), shown(d.name), type)}};
  const auto* map = std::find_if(kMapBytes.begin(), kMapBytes.end(), [&](const auto& m) { return m.first == type; });
  if (map == kMapBytes.end()) c.fail("grid '{}' has a map of type '{}', which OpenVDB does not know", shown(d.name), type);
  c.skip(map->second, "the map");
}

// The walk through one float tree (Tree_float_5_4_3, values 4 bytes, or 2 saved as half).
struct Tree {
  Cursor& c;
  std::uint32_t compression = 0;
  std::uint64_t value_bytes = 4;
  // Each leaf's value mask in the order of the topology, as its count of active values and a hash
  // (the buffers repeat the mask; OpenVDB seeks over the copy and counts by the topology's).
  struct Leaf {
    std::uint64_t active, hash;
  };
  std::vector<Leaf> leaves;

  static std::uint64_t count_on(const std::string& mask) {
    std::uint64_t n = 0;
    for (const char byte : mask) n += static_cast<std::uint64_t>(std::popcount(static_cast<unsigned char>(byte)));
    return n;
  }
  static Leaf leaf(const std::string& mask) { return {count_on(mask), std::hash<std::string>{}(mask)}; }

  // io::readCompressedValues for a node of `values` values, `active` of them on in its value mask
  // of `mask_bytes` bytes.
  void compressed_values(std::uint64_t values, std::uint64_t active, std::uint64_t mask_bytes, bool decode) {
    const auto kind = c.get<std::int8_t>("a node's value flag");
    if (kind == 2 || kind == 4 || kind == 5) c.skip(kind == 5 ? 8 : 4, "a node's inactive values");
    if (kind == 3 || kind == 4 || kind == 5) c.skip(mask_bytes, "a node's selection mask");
    const bool only_active = (compression & kActiveMask) != 0 && kind != 6;
    chunk((only_active ? active : values) * value_bytes, decode);
  }

  // readData: blosc or zip, each after a 64-bit size (negative or zero: that many raw bytes), or raw.
  // With `decode`, a compressed chunk (its size checked first) is also decompressed, by OpenVDB's
  // own functions: a root child's topology that throws while OpenVDB reads it is never freed
  // (RootNode::readTopology), so what would throw there is refused here.
  void chunk(std::uint64_t expected, bool decode) {
    if ((compression & (kBlosc | kZip)) == 0) return c.skip(expected, "a node's values");
    const std::uint64_t at = c.pos();
    const auto size = c.get<std::int64_t>("a chunk size");
    if (size <= 0) {
      const std::uint64_t raw = std::uint64_t{0} - static_cast<std::uint64_t>(size);
      if (raw != expected)
        c.fail("the uncompressed chunk at byte {} holds {} bytes where its node needs {}", c.pos() - 8, raw, expected);
      return c.skip(raw, "an uncompressed chunk");
    }
    const auto bytes = static_cast<std::uint64_t>(size);
    if (compression & kBlosc) blosc_header(c, bytes, expected, "a blosc chunk");
    else c.skip(bytes, "a zip chunk");
    if (decode) decompress(at, expected);
  }

  void decompress(std::uint64_t at, std::uint64_t expected) {
    std::vector<char> values(static_cast<std::size_t>(expected));
    try {
      std::istream& in = c.stream_at(at);
      if (compression & kBlosc) openvdb::io::bloscFromStream(in, values.data(), values.size());
      else openvdb::io::unzipFromStream(in, values.data(), values.size());
    } catch (const std::exception& e) {
      c.fail("the {} chunk at byte {} does not decompress to the {} bytes of its node: {}",
             (compression & kBlosc) ? "blosc" : "zip", at, expected, e.what());
    }
    c.seek(c.pos());  // back where the walk is
  }

  // InternalNode::readTopology of a node of 2^(3 log2_dim) entries; its children are internal
  // nodes of log2_dim 4 or leaves (log2_dim 3, whose topology is their value mask).
  void internal_topology(int log2_dim) {
    const std::uint64_t entries = std::uint64_t{1} << (3 * log2_dim);
    const std::string child_mask = c.bytes(entries / 8, "a child mask");
    const std::string value_mask = c.bytes(entries / 8, "a value mask");
    compressed_values(entries, count_on(value_mask), value_mask.size(), true);
    for (std::size_t byte = 0; byte < child_mask.size(); ++byte)
      for (int bit = 0; bit < 8; ++bit) {
        if ((static_cast<unsigned char>(child_mask[byte]) >> bit & 1u) == 0) continue;
        if (log2_dim == 5) internal_topology(4);
        else leaves.push_back(leaf(c.bytes(64, "a leaf's value mask")));
      }
  }

  // Tree::readTopology then readBuffers. The buffers follow the root's children in the order of
  // its std::map (by origin), each leaf's values counted by its topology's value mask.
  void walk() {
    c.skip(4 + 4, "the tree's buffer count and background");
    const auto tiles = c.get<std::uint32_t>("the root's tile count");
    const auto children = c.get<std::uint32_t>("the root's child count");
    c.skip(std::uint64_t{tiles} * 17, "the root's tiles");
    c.need(std::uint64_t{children} * (12 + 2 * 4096 + 1), "the root's children");  // origin, masks, flag
    struct Child {
      std::array<std::int32_t, 3> origin;
      std::size_t first_leaf, leaves;
    };
    std::vector<Child> order;
    for (std::uint32_t i = 0; i < children; ++i) {
      const auto at = c.pos();
      Child child{};
      for (auto& x : child.origin) x = c.get<std::int32_t>("a root child's origin");
      if (std::any_of(child.origin.begin(), child.origin.end(), [](std::int32_t x) { return (x & 4095) != 0; }))
        c.fail("the root child at byte {} has origin ({}, {}, {}), not a multiple of 4096", at, child.origin[0],
               child.origin[1], child.origin[2]);
      child.first_leaf = leaves.size();
      internal_topology(5);
      child.leaves = leaves.size() - child.first_leaf;
      order.push_back(child);
    }
    std::sort(order.begin(), order.end(), [](const Child& a, const Child& b) { return a.origin < b.origin; });
    for (std::size_t i = 1; i < order.size(); ++i)
      if (order[i].origin == order[i - 1].origin) c.fail("two root children share the origin of the one at {}", i);
    for (const Child& child : order)
      for (std::size_t l = child.first_leaf; l < child.first_leaf + child.leaves; ++l) {
        const Leaf in_buffers = leaf(c.bytes(64, "a leaf's value mask"));
        if (in_buffers.active != leaves[l].active || in_buffers.hash != leaves[l].hash)
          c.fail("a leaf's value mask at byte {} differs from its topology", c.pos() - 64);
        compressed_values(512, leaves[l].active, 64, false);  // a leaf's buffer: freed with the tree
      }
  }
};

// Archive::readGrid: compression flags, metadata, transform, then (float grids that are not
// instances of another) topology and buffers. Other grids are read no further by Bouguer.
void grid(Cursor& c, const Descriptor& d, const std::vector<Descriptor>& all) {
  c.seek(d.grid_pos);
  const auto compression = c.get<std::uint32_t>("a grid's compression flags");
  metadata(c, "a grid's metadata");
  transform(c, d);
  if (d.type != kFloatTree) return;
  if (!d.parent.empty()) {
    const bool float_parent = std::any_of(all.begin(), all.end(), [&](const Descriptor& p) {
      return p.name == d.parent && p.type == d.type && p.half == d.half && p.parent.empty();
    });
    if (!float_parent) c.fail("grid '{}' is an instance of '{}', which is not a float grid of the file", shown(d.name),
                              shown(d.parent));
    return;
  }
  Tree tree{c, compression, d.half ? 2u : 4u, {}};
  tree.walk();
  // OpenVDB reads on from where the walk ended; a tree that ends elsewhere than its descriptor
  // says was not read as it was written.
  if (c.pos() != d.end_pos)
    c.fail("grid '{}' ends at byte {}, where its descriptor says {}", shown(d.name), c.pos(), d.end_pos);
}

}  // namespace

Result check(const std::string& path, bool grids) {
  try {
    Cursor c(path);
    header(c);
    metadata(c, "the file's metadata");
    const std::vector<Descriptor> all = descriptors(c);
    if (grids)
      for (const Descriptor& d : all) grid(c, d, all);
    return {};
  } catch (const Problem& p) {
    return p.result;
  }
}

}  // namespace bouguer::vdb_layout
