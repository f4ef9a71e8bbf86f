// Two triangles that cross, through dvh.hpp and the shared library: exits 0 only when the one
// pair is found.
#include <dvh.hpp>
#include <cstdio>
#include <vector>

int main() {
    const std::vector<double> a_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<double> b_pos = {0.2, 0.2, -1, 0.2, 0.2, 1, 1, 1, 0};
    const std::vector<uint32_t> tri = {0, 1, 2};
    try {
        dvh::Mesh a(a_pos, tri), b(b_pos, tri);
        dvh::Pairs pairs;
        dvh::collide(a, nullptr, b, nullptr, dvh::QueryOptions{}, pairs);
        const auto found = pairs.view();
        if (found.size() != 1 || found[0].a != 0 || found[0].b != 0) {
            std::fprintf(stderr, "expected the pair (0, 0), got %zu pairs\n", found.size());
            return 1;
        }
        std::printf("dvh %s through CMake (shared, C++): 1 pair\n", dvh::version());
    } catch (const dvh::Error& e) {
        std::fprintf(stderr, "dvh: %s\n", e.what());
        return 1;
    }
    return 0;
}
