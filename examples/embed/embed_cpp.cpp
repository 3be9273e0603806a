// romrt.h from C++: the header compiles as C++ and links against the C runtime. Opens the asset
// given on the command line, takes one step, and sets up what a GPU renderer needs: the rest
// positions X and basis rows U of the shown vertices once (std::vector sized by the model; every
// romrt call is told the buffer's capacity), then the r reduced coordinates q per frame for a
// vertex shader computing x = X + U q.
#include <algorithm>
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
    if (romrt_version() / 10000 != ROMRT_VERSION_MAJOR) { // a shared library from another major version
        std::fprintf(stderr, "embed_cpp: runtime %d, header %d\n", romrt_version(), ROMRT_VERSION_NUMBER);
        return 1;
    }
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
    std::printf("embed_cpp: one step of r = %zu done\n", romrt_reduced_size(m));

    // Once: X (into an interleaved position + normal buffer, stride 6) and U for the GPU.
    const size_t n = romrt_shown_count(m), r = romrt_reduced_size(m);
    std::vector<romrt_real> vertices(6 * n), rows(3 * n * r), q(r);
    if (romrt_rest_positions(m, vertices.data(), vertices.size(), 6, &err) != ROMRT_OK ||
        romrt_basis_rows(m, rows.data(), rows.size(), &err) != ROMRT_OK) {
        std::fprintf(stderr, "embed_cpp: %s\n", err.message);
        return 1;
    }
    // Per frame: step, then q (r reals) is all that goes to the GPU.
    if (romrt_step(m, &err) != ROMRT_OK || romrt_reduced_coordinates(m, q.data(), q.size(), &err) != ROMRT_OK) {
        std::fprintf(stderr, "embed_cpp: %s\n", err.message);
        return 1;
    }
    // What the vertex shader computes for the last shown vertex, against the runtime's own positions.
    std::vector<romrt_real> x(3 * n);
    if (romrt_positions(m, x.data(), x.size(), 3, &err) != ROMRT_OK) return 1;
    double worst = 0;
    for (size_t k = 0; k < 3; k++) {
        size_t row = 3 * (n - 1) + k;
        double s = vertices[6 * (n - 1) + k];
        for (size_t j = 0; j < r; j++) s += static_cast<double>(rows[row * r + j]) * q[j];
        worst = std::max(worst, s > x[row] ? s - x[row] : x[row] - s);
    }
    std::printf("embed_cpp: %zu vertices x %zu rows uploaded once, %zu reals a frame; shader sum off by %.1e m\n", n, r,
                r, worst);
    return 0;
}
