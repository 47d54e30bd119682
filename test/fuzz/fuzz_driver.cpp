// Corpus regression for a libFuzzer harness, built with the project's own
// compiler (see cmake/Fuzz.cmake):
//
//   fuzz_NAME_regression [--mutations N] [--seed S] CORPUS_DIR_OR_FILE...
//
// Runs LLVMFuzzerTestOneInput on every seed file (sorted by name), then on
// N inputs derived from them by deterministic pseudo-random mutations (bit
// flips, byte overwrites, inserts, erases, truncation, splices, random
// blobs), so the same binary always exercises the same inputs. A crash or
// sanitizer report fails the ctest; otherwise it prints what it ran.
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) __attribute__((weak));

namespace {

// Mutated inputs stay below this size (LiDAR packets are 1.2 KiB, serial
// frames smaller; a few packets' worth is enough to reach every path).
constexpr size_t kMaxInput = 8192;

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void collect(const std::string& path, std::vector<std::string>* files) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    std::fprintf(stderr, "fuzz driver: %s: %s\n", path.c_str(), std::strerror(errno));
    std::exit(2);
  }
  if (!S_ISDIR(st.st_mode)) {
    files->push_back(path);
    return;
  }
  DIR* d = ::opendir(path.c_str());
  std::vector<std::string> names;
  while (dirent* e = ::readdir(d)) {
    if (e->d_name[0] == '.') continue;
    names.push_back(path + "/" + e->d_name);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  for (const auto& n : names) collect(n, files);
}

std::vector<uint8_t> mutate(const std::vector<std::vector<uint8_t>>& seeds, std::mt19937_64& rng) {
  std::vector<uint8_t> x;
  if (!seeds.empty() && rng() % 8 != 0) x = seeds[rng() % seeds.size()];
  const int edits = 1 + static_cast<int>(rng() % 8);
  for (int e = 0; e < edits; ++e) {
    const size_t n = x.size();
    switch (rng() % 8) {
      case 0:  // flip a bit
        if (n) x[rng() % n] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      case 1:  // overwrite a byte, often with an interesting value
        if (n) {
          static const uint8_t interesting[] = {0x00, 0xFF, 0x7F, 0x80, 0xEE, 0x01, 0x37, 0x39};
          x[rng() % n] = (rng() % 2) ? interesting[rng() % sizeof(interesting)] : static_cast<uint8_t>(rng());
        }
        break;
      case 2: {  // insert random bytes
        size_t pos = n ? rng() % (n + 1) : 0;
        size_t k = 1 + rng() % 16;
        std::vector<uint8_t> ins(k);
        for (auto& b : ins) b = static_cast<uint8_t>(rng());
        x.insert(x.begin() + static_cast<long>(pos), ins.begin(), ins.end());
        break;
      }
      case 3:  // erase a range
        if (n) {
          size_t pos = rng() % n;
          size_t k = 1 + rng() % std::min<size_t>(n - pos, 64);
          x.erase(x.begin() + static_cast<long>(pos), x.begin() + static_cast<long>(pos + k));
        }
        break;
      case 4:  // truncate
        if (n) x.resize(rng() % n);
        break;
      case 5:  // splice with another seed
        if (!seeds.empty()) {
          const auto& other = seeds[rng() % seeds.size()];
          if (!other.empty()) {
            size_t from = rng() % other.size();
            size_t k = 1 + rng() % (other.size() - from);
            size_t pos = n ? rng() % (n + 1) : 0;
            x.insert(x.begin() + static_cast<long>(pos), other.begin() + static_cast<long>(from),
                     other.begin() + static_cast<long>(from + k));
          }
        }
        break;
      case 6:  // overwrite a 16-bit field
        if (n >= 2) {
          size_t pos = rng() % (n - 1);
          x[pos] = static_cast<uint8_t>(rng());
          x[pos + 1] = static_cast<uint8_t>(rng());
        }
        break;
      default: {  // a random blob
        x.resize(rng() % 2048);
        for (auto& b : x) b = static_cast<uint8_t>(rng());
        break;
      }
    }
    if (x.size() > kMaxInput) x.resize(kMaxInput);
  }
  return x;
}

}  // namespace

int main(int argc, char** argv) {
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  long mutations = 10000;
  uint64_t seed = 0x5eed;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--mutations" && i + 1 < argc) {
      mutations = std::strtol(argv[++i], nullptr, 10);
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else {
      collect(a, &files);
    }
  }
  std::vector<std::vector<uint8_t>> seeds;
  for (const auto& f : files) {
    seeds.push_back(read_file(f));
    LLVMFuzzerTestOneInput(seeds.back().data(), seeds.back().size());
  }
  static const uint8_t kEmpty = 0;
  LLVMFuzzerTestOneInput(&kEmpty, 0);
  std::mt19937_64 rng(seed);
  for (long i = 0; i < mutations; ++i) {
    std::vector<uint8_t> x = mutate(seeds, rng);
    LLVMFuzzerTestOneInput(x.data(), x.size());
  }
  std::printf("fuzz driver: %zu seed files, %ld mutated inputs, no crash\n", seeds.size(), mutations);
  return 0;
}
