#include "geometry.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace xc {

namespace {

// Next line that is not empty once comments are stripped.
bool next_line(std::istream& in, std::string& line, size_t& number) {
    while (std::getline(in, line)) {
        number++;
        auto hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        if (line.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
}

[[noreturn]] void bad(const std::string& path, size_t line, const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

MeshData load_off(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::string line;
    size_t number = 0;
    if (!next_line(in, line, number)) bad(path, number, "empty file");
    std::istringstream header(line);
    std::string magic;
    header >> magic;
    if (magic.size() < 3 || magic.compare(magic.size() - 3, 3, "OFF") != 0) bad(path, number, "not an OFF file");
    size_t nv = 0, nf = 0;
    if (!(header >> nv >> nf)) {
        if (!next_line(in, line, number)) bad(path, number, "missing counts");
        std::istringstream counts(line);
        if (!(counts >> nv >> nf)) bad(path, number, "bad counts");
    }
    MeshData m;
    m.pos.reserve(nv * 3);
    for (size_t i = 0; i < nv; i++) {
        if (!next_line(in, line, number)) bad(path, number, "missing vertices");
        std::istringstream v(line);
        double x, y, z;
        if (!(v >> x >> y >> z)) bad(path, number, "bad vertex");
        m.pos.insert(m.pos.end(), {x, y, z});
    }
    for (size_t f = 0; f < nf; f++) {
        if (!next_line(in, line, number)) bad(path, number, "missing faces");
        std::istringstream face(line);
        size_t k = 0;
        face >> k;
        std::vector<uint32_t> idx(k);
        for (auto& i : idx)
            if (!(face >> i) || i >= nv) bad(path, number, "bad face index");
        for (size_t j = 1; j + 1 < k; j++) m.tris.insert(m.tris.end(), {idx[0], idx[j], idx[j + 1]});
    }
    return m;
}

MeshData subdivide(const MeshData& m) {
    MeshData out;
    out.pos = m.pos;
    out.tris.reserve(m.tris.size() * 4);
    std::unordered_map<uint64_t, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
        uint64_t key = ((uint64_t)std::min(a, b) << 32) | std::max(a, b);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        uint32_t id = (uint32_t)(out.pos.size() / 3);
        for (int k = 0; k < 3; k++) out.pos.push_back(0.5 * (out.pos[3 * (size_t)a + k] + out.pos[3 * (size_t)b + k]));
        mid.emplace(key, id);
        return id;
    };
    for (size_t t = 0; t < m.triangles(); t++) {
        uint32_t a = m.tris[3 * t], b = m.tris[3 * t + 1], c = m.tris[3 * t + 2];
        uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
        out.tris.insert(out.tris.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    return out;
}

MeshData subdivided_to(const MeshData& m, size_t triangles) {
    MeshData out = m;
    while (out.triangles() < triangles) out = subdivide(out);
    return out;
}

void bounds(const MeshData& m, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) {
        lo[k] = HUGE_VAL;
        hi[k] = -HUGE_VAL;
    }
    for (size_t i = 0; i < m.vertices(); i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = std::min(lo[k], m.pos[3 * i + k]);
            hi[k] = std::max(hi[k], m.pos[3 * i + k]);
        }
}

void normalize(MeshData& m, double size) {
    double lo[3], hi[3];
    bounds(m, lo, hi);
    double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    double s = extent > 0 ? size / extent : 1.0;
    for (size_t i = 0; i < m.vertices(); i++)
        for (int k = 0; k < 3; k++) m.pos[3 * i + k] = (m.pos[3 * i + k] - 0.5 * (lo[k] + hi[k])) * s;
}

MeshData grid(int n, double size) {
    MeshData m;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) m.pos.insert(m.pos.end(), {i * size / n, j * size / n, 0.0});
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2, d = a + (uint32_t)n + 1;
            m.tris.insert(m.tris.end(), {a, b, c, a, c, d});
        }
    return m;
}

MeshData terrain(int n, double size, double amplitude, uint64_t seed) {
    MeshData m = grid(n, size);
    Rng rng(seed);
    double fx = rng.range(1, 3), fy = rng.range(1, 3), px = rng.range(0, 6.28), py = rng.range(0, 6.28);
    for (size_t i = 0; i < m.vertices(); i++) {
        double x = m.pos[3 * i] / size, y = m.pos[3 * i + 1] / size;
        m.pos[3 * i + 2] = amplitude * std::sin(6.283185307179586 * fx * x + px) * std::cos(6.283185307179586 * fy * y + py);
    }
    return m;
}

Morph Morph::random(const MeshData& m, int count, double amplitude, uint64_t seed) {
    Rng rng(seed);
    double lo[3], hi[3];
    bounds(m, lo, hi);
    double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    Morph morph;
    morph.y_lo = lo[1];
    morph.y_hi = hi[1];
    for (int c = 0; c < count; c++) {
        Control k;
        size_t v = (size_t)(rng.next() % m.vertices());
        double d[3] = {rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1)};
        double n = std::max(1e-9, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        for (int a = 0; a < 3; a++) {
            k.point[a] = m.pos[3 * v + a];
            k.displacement[a] = d[a] / n * amplitude * size;
        }
        k.width = 0.25 * size;
        k.phase = rng.unit();
        morph.controls.push_back(k);
    }
    return morph;
}

void Morph::apply(const std::vector<double>& rest, double t, std::vector<double>& out) const {
    out.resize(rest.size());
    std::vector<double> pull(controls.size() * 3), spread(controls.size());
    for (size_t c = 0; c < controls.size(); c++) {
        double s = std::sin(6.283185307179586 * (t + controls[c].phase));
        for (int a = 0; a < 3; a++) pull[3 * c + a] = controls[c].displacement[a] * s;
        if (planar) pull[3 * c + 2] = 0.0;
        spread[c] = -0.5 / (controls[c].width * controls[c].width);
    }
    double span = y_hi > y_lo ? y_hi - y_lo : 1.0;
    for (size_t i = 0; i < rest.size() / 3; i++) {
        const double* p = &rest[3 * i];
        double q[3] = {p[0], p[1], p[2]};
        double height = std::min(1.0, std::max(0.0, (p[1] - y_lo) / span));
        double scale = 1.0 + upper_bias * (2.0 * height * height - 1.0);
        for (size_t c = 0; c < controls.size(); c++) {
            const double* k = controls[c].point;
            double r2 = (p[0] - k[0]) * (p[0] - k[0]) + (p[1] - k[1]) * (p[1] - k[1]) + (p[2] - k[2]) * (p[2] - k[2]);
            double w = std::exp(spread[c] * r2) * scale;
            for (int a = 0; a < 3; a++) q[a] += w * pull[3 * c + a];
        }
        out[3 * i] = q[0];
        out[3 * i + 1] = q[1];
        out[3 * i + 2] = q[2];
    }
}

Pose Pose::from_axis_angle(const double axis[3], double angle, const double translation[3]) {
    double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double x = axis[0] / n, y = axis[1] / n, z = axis[2] / n;
    double c = std::cos(angle), s = std::sin(angle), k = 1 - c;
    Pose p;
    double r[9] = {c + x * x * k,     x * y * k - z * s, x * z * k + y * s,
                   y * x * k + z * s, c + y * y * k,     y * z * k - x * s,
                   z * x * k - y * s, z * y * k + x * s, c + z * z * k};
    std::copy(r, r + 9, p.r);
    std::copy(translation, translation + 3, p.t);
    return p;
}

void apply_pose(const Pose& pose, const std::vector<double>& local, std::vector<double>& world) {
    world.resize(local.size());
    const double* r = pose.r;
    for (size_t i = 0; i < local.size() / 3; i++) {
        const double* p = &local[3 * i];
        for (int k = 0; k < 3; k++) {
            double v = r[3 * k] * p[0];
            v = v + r[3 * k + 1] * p[1];
            v = v + r[3 * k + 2] * p[2];
            world[3 * i + k] = v + pose.t[k];
        }
    }
}

}  // namespace xc
