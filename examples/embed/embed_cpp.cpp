// romrt.h from C++: the header compiles as C++ and links against the C runtime. Opens the asset
// given on the command line and takes one step.
#include <cstdio>
#include <fstream>
#include <vector>

#include "romrt.h" // runtime/ in the tree (-Iruntime), <prefix>/include once installed

int main(int argc, char **argv)
{
    if (argc < 2) return 2;
    std::ifstream in(argv[1], std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<double> asset((bytes.size() + 7) / 8); // 8-byte aligned storage
    std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char *>(asset.data()));
    size_t arena_bytes = 0;
    romrt_error err;
    if (romrt_arena_size(asset.data(), bytes.size(), &arena_bytes, &err) != ROMRT_OK) {
        std::fprintf(stderr, "embed_cpp: %s\n", err.message);
        return 1;
    }
    std::vector<double> arena((arena_bytes + 7) / 8);
    romrt_model *m = nullptr;
    if (romrt_open(asset.data(), bytes.size(), arena.data(), arena_bytes, &m, &err) != ROMRT_OK ||
        romrt_step(m, &err) != ROMRT_OK) {
        std::fprintf(stderr, "embed_cpp: %s\n", err.message);
        return 1;
    }
    std::printf("embed_cpp: one step of r = %d done\n", romrt_reduced_size(m));
    return 0;
}
