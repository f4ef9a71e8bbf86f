#include "scenes.hpp"

#include <cmath>
#include <cstdio>

namespace xc {

namespace {

constexpr double kTau = 6.283185307179586;

MeshData cgal_mesh(const SceneOptions& o, const std::string& name, size_t min_triangles, double size) {
    MeshData m = subdivided_to(load_off(o.data_dir + "/" + name + ".off"), min_triangles);
    normalize(m, size);
    return m;
}

void all_pairs(Scene& s) {
    for (int i = 0; i < (int)s.objects.size(); i++)
        for (int j = i + 1; j < (int)s.objects.size(); j++) s.pairs.emplace_back(i, j);
}

// Scene 1 of the paper: many small objects moving and deforming, every pair tested.
Scene many(const SceneOptions& o) {
    Scene s;
    int count = o.full ? 40 : 6;
    MeshData base = o.full ? cgal_mesh(o, "lion", 14000, 1.0) : cgal_mesh(o, "elephant", 5000, 1.0);
    s.name = "many";
    s.description = std::to_string(count) + " objects of " + std::to_string(base.triangles()) +
                    " triangles moving and deforming, every pair tested";
    Rng rng(1);
    int nx = o.full ? 5 : 3, ny = o.full ? 4 : 2;
    for (int i = 0; i < count; i++) {
        Object obj;
        obj.name = "object" + std::to_string(i);
        obj.rest = base;
        obj.morph = Morph::random(base, 3, 0.06, 100 + (uint64_t)i);
        double centre[3] = {0.8 * (i % nx), 0.8 * ((i / nx) % ny), 0.8 * (i / (nx * ny))};
        double axis[3] = {rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1)};
        double spin = rng.range(0.5, 1.5), phase = rng.unit(), drift = rng.range(0, kTau);
        double dir[3] = {std::cos(drift), std::sin(drift), rng.range(-0.5, 0.5)};
        obj.motion = [=](double t) {
            double a = 0.16 * std::sin(kTau * (t + phase));
            double tr[3] = {centre[0] + a * dir[0], centre[1] + a * dir[1], centre[2] + a * dir[2]};
            return Pose::from_axis_angle(axis, spin * kTau * t, tr);
        };
        s.objects.push_back(std::move(obj));
    }
    all_pairs(s);
    return s;
}

// Scene 2: three medium meshes deforming into each other, larger deformation in their upper parts.
Scene medium(const SceneOptions& o) {
    Scene s;
    s.name = "medium";
    struct Spec {
        const char* mesh;
        size_t full, quick;
        double x;
    } specs[3] = {{"elephant", 84000, 5000, -0.32}, {"elephant", 84000, 5000, 0.32}, {"mannequin-devil", 100000, 6000, 0.0}};
    for (int i = 0; i < 3; i++) {
        Object obj;
        obj.name = std::string(specs[i].mesh) + std::to_string(i);
        obj.rest = cgal_mesh(o, specs[i].mesh, o.full ? specs[i].full : specs[i].quick, 1.0);
        obj.morph = Morph::random(obj.rest, 4, 0.08, 200 + (uint64_t)i);
        obj.morph.upper_bias = 1.0;
        double x = specs[i].x, z = i == 2 ? 0.25 : 0.0, phase = 0.3 * i;
        obj.motion = [=](double t) {
            double axis[3] = {0, 1, 0};
            double tr[3] = {x + 0.06 * std::sin(kTau * (t + phase)), 0.0, z};
            return Pose::from_axis_angle(axis, 0.3 * std::sin(kTau * t + phase), tr);
        };
        s.objects.push_back(std::move(obj));
    }
    s.description = "3 meshes (" + std::to_string(s.objects[0].rest.triangles()) + ", " +
                    std::to_string(s.objects[1].rest.triangles()) + ", " + std::to_string(s.objects[2].rest.triangles()) +
                    " triangles) deforming into each other, more at the top";
    all_pairs(s);
    return s;
}

// Scene 3: two large meshes colliding at their extremities. The right one is the left one turned
// half a turn about the vertical, placed so that their farthest-reaching vertices (the extremity
// along x) meet, then pushed into each other by a varying depth.
Scene large(const SceneOptions& o) {
    Scene s;
    s.name = "large";
    MeshData base = o.full ? cgal_mesh(o, "refined_elephant", 350000, 1.0) : cgal_mesh(o, "armadillo", 50000, 1.0);
    size_t tip = 0;
    for (size_t v = 1; v < base.vertices(); v++)
        if (base.pos[3 * v] > base.pos[3 * tip]) tip = v;
    double px = base.pos[3 * tip], pz = base.pos[3 * tip + 2];
    for (int i = 0; i < 2; i++) {
        Object obj;
        obj.name = i == 0 ? "left" : "right";
        obj.rest = base;
        obj.morph = Morph::random(base, 4, 0.05, 300 + (uint64_t)i);
        obj.motion = [=](double t) {
            double axis[3] = {0, 1, 0};
            double depth = 0.03 + 0.03 * std::sin(kTau * t);  // how far the tips pass each other
            double tr[3] = {i == 0 ? -px + 0.5 * depth : px - 0.5 * depth, 0.0, i == 0 ? 0.0 : 2.0 * pz};
            return Pose::from_axis_angle(axis, i == 0 ? 0.0 : 3.141592653589793, tr);
        };
        s.objects.push_back(std::move(obj));
    }
    s.description = "2 meshes of " + std::to_string(base.triangles()) + " triangles meeting at their extremities";
    all_pairs(s);
    return s;
}

// Stress: two sheets in one plane, one turning and sliding over the other; every contact coplanar.
Scene coplanar(const SceneOptions& o) {
    Scene s;
    s.name = "coplanar";
    int n = o.full ? 160 : 20;
    for (int i = 0; i < 2; i++) {
        Object obj;
        obj.name = i == 0 ? "sheet" : "turning sheet";
        obj.rest = grid(n, 1.0);
        obj.morph = Morph::random(obj.rest, 3, 0.03, 400 + (uint64_t)i);
        obj.morph.planar = true;
        obj.motion = [=](double t) {
            double axis[3] = {0, 0, 1};
            double tr[3] = {i == 0 ? 0.0 : 0.3 + 0.2 * std::sin(kTau * t), i == 0 ? 0.0 : 0.25, 0.0};
            return Pose::from_axis_angle(axis, i == 0 ? 0.0 : 0.5 * kTau * t, tr);
        };
        s.objects.push_back(std::move(obj));
    }
    s.description = "2 coplanar sheets of " + std::to_string(s.objects[0].rest.triangles()) + " triangles";
    all_pairs(s);
    return s;
}

// Stress: a mesh against an exact copy of itself (same deformation, same pose): every triangle
// touches itself and its neighbours.
Scene copy(const SceneOptions& o) {
    Scene s;
    s.name = "copy";
    MeshData base = o.full ? cgal_mesh(o, "bunny00", 70000, 1.0) : cgal_mesh(o, "elephant", 5000, 1.0);
    Morph morph = Morph::random(base, 3, 0.05, 500);
    for (int i = 0; i < 2; i++) {
        Object obj;
        obj.name = i == 0 ? "mesh" : "copy";
        obj.rest = base;
        obj.morph = morph;
        obj.motion = [](double t) {
            double axis[3] = {1, 1, 0};
            double tr[3] = {0.1, 0.2, 0.3};
            return Pose::from_axis_angle(axis, t, tr);
        };
        s.objects.push_back(std::move(obj));
    }
    s.description = "a mesh of " + std::to_string(base.triangles()) + " triangles against an exact copy";
    all_pairs(s);
    return s;
}

// Stress: a bumpy sheet and its copy shifted sideways by a tiny offset. The two surfaces cross
// along curves everywhere and nearly coincide elsewhere: nearly coplanar pairs by the thousand.
Scene near_touching(const SceneOptions& o, double offset) {
    Scene s;
    char gap[32];
    std::snprintf(gap, sizeof gap, "%.0e", offset);
    s.name = std::string("near-") + gap;
    int n = o.full ? 160 : 24;
    MeshData base = terrain(n, 1.0, 0.1, 7);
    Morph morph = Morph::random(base, 3, 0.03, 600);
    for (int i = 0; i < 2; i++) {
        Object obj;
        obj.name = i == 0 ? "terrain" : "shifted";
        obj.rest = base;
        obj.morph = morph;
        double shift = i == 0 ? 0.0 : offset;
        obj.motion = [=](double t) {
            double axis[3] = {0, 0, 1};
            double tr[3] = {shift, 0.5 * shift, 0.0};
            return Pose::from_axis_angle(axis, 0.2 * t, tr);
        };
        s.objects.push_back(std::move(obj));
    }
    s.description = "a terrain of " + std::to_string(base.triangles()) + " triangles and its copy shifted sideways by " + gap;
    all_pairs(s);
    return s;
}

// Turns every vertex about the vertical (y) axis through the origin by `angle(vertex)`.
template <typename Angle>
void turn_about_y(const std::vector<double>& rest, Angle angle, std::vector<double>& out) {
    out = rest;
    for (size_t i = 0; i < rest.size() / 3; i++) {
        const double* p = &rest[3 * i];
        double a = angle(p), c = std::cos(a), s = std::sin(a);
        out[3 * i] = c * p[0] + s * p[2];
        out[3 * i + 2] = -s * p[0] + c * p[2];
    }
}

// Self-collision: a sheet rolled up tighter and tighter, one and three quarter turns at the end,
// on a radius that wobbles with the angle so that the second turn crosses the first (rather than
// lying inside it), and a little helical so that the crossings run slantwise.
SelfScene roll(const SceneOptions& o) {
    SelfScene s;
    s.name = "roll";
    s.rest = grid(o.full ? 200 : 32, 1.0);
    s.description = "a sheet of " + std::to_string(s.rest.triangles()) + " triangles rolled until it crosses itself";
    std::vector<double> rest = s.rest.pos;
    s.at = [rest](double t, std::vector<double>& out) {
        out = rest;
        if (t <= 0) return;
        double turn = 1.75 * kTau * t, radius = 1.0 / turn;
        for (size_t i = 0; i < rest.size() / 3; i++) {
            double x = rest[3 * i], y = rest[3 * i + 1];
            double phi = turn * x + 0.4 * t * (y - 0.5);
            double r = radius * (1.0 + 0.3 * std::sin(1.5 * phi));
            out[3 * i] = r * std::sin(phi);
            out[3 * i + 2] = radius - r * std::cos(phi);
        }
    };
    return s;
}

// Self-collision: a sheet pulled about by eight wide bumps in random directions, growing with
// time until neighbouring regions fold over each other.
SelfScene crumple(const SceneOptions& o) {
    SelfScene s;
    s.name = "crumple";
    s.rest = grid(o.full ? 128 : 24, 1.0);
    s.description = "a sheet of " + std::to_string(s.rest.triangles()) + " triangles crumpled through itself";
    struct Bump {
        double centre[2], pull[3];
    };
    std::vector<Bump> bumps;
    Rng rng(800);
    for (int k = 0; k < 8; k++) {
        Bump b;
        b.centre[0] = rng.unit();
        b.centre[1] = rng.unit();
        double d[3] = {rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1)};
        double n = std::max(1e-9, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        for (int a = 0; a < 3; a++) b.pull[a] = 0.5 * d[a] / n;
        bumps.push_back(b);
    }
    std::vector<double> rest = s.rest.pos;
    s.at = [rest, bumps](double t, std::vector<double>& out) {
        out = rest;
        for (size_t i = 0; i < rest.size() / 3; i++)
            for (const auto& b : bumps) {
                double dx = rest[3 * i] - b.centre[0], dy = rest[3 * i + 1] - b.centre[1];
                double w = t * std::exp(-(dx * dx + dy * dy) / (2 * 0.18 * 0.18));
                for (int a = 0; a < 3; a++) out[3 * i + a] += w * b.pull[a];
            }
    };
    return s;
}

// Self-collision: the elephant folded about a vertical axis through its middle, front and back
// halves turning opposite ways (110 degrees each at the end) until they pass through each other;
// the inside of the bend is squeezed through itself first.
SelfScene fold(const SceneOptions& o) {
    SelfScene s;
    s.name = "fold";
    s.rest = load_off(o.data_dir + (o.full ? "/refined_elephant.off" : "/elephant.off"));
    normalize(s.rest, 1.0);
    s.description = "an elephant of " + std::to_string(s.rest.triangles()) + " triangles folded through itself";
    std::vector<double> rest = s.rest.pos;
    s.at = [rest](double t, std::vector<double>& out) {
        double angle = t * 110.0 / 360.0 * kTau;
        turn_about_y(rest, [&](const double* p) { return angle * std::max(-1.0, std::min(1.0, p[0] / 0.08)); }, out);
    };
    return s;
}

// Self-collision: the armadillo twisted about its vertical axis by an angle growing with the
// distance from the axis along x (200 degrees at the hands at the end): both arms swing forward
// round the body until they cross each other, and the shoulders shear.
SelfScene twist(const SceneOptions& o) {
    SelfScene s;
    s.name = "twist";
    MeshData base = load_off(o.data_dir + "/armadillo.off");
    s.rest = o.full ? subdivided_to(base, 200000) : base;
    normalize(s.rest, 1.0);
    s.description = "an armadillo of " + std::to_string(s.rest.triangles()) + " triangles twisted until its arms cross";
    double reach = 0;
    for (size_t i = 0; i < s.rest.vertices(); i++) reach = std::max(reach, std::fabs(s.rest.pos[3 * i]));
    std::vector<double> rest = s.rest.pos;
    s.at = [rest, reach](double t, std::vector<double>& out) {
        double angle = t * 200.0 / 360.0 * kTau;
        turn_about_y(rest, [&](const double* p) { return angle * p[0] / reach; }, out);
    };
    return s;
}

}  // namespace

Pose place_object(Object& o, double t, std::vector<double>& local, std::vector<double>& world) {
    if (o.deforms)
        o.morph.apply(o.rest.pos, t, local);
    else
        local = o.rest.pos;
    Pose pose = o.motion(t);
    apply_pose(pose, local, world);
    return pose;
}

std::vector<Scene> make_scenes(const SceneOptions& o) {
    std::vector<Scene> scenes;
    scenes.push_back(many(o));
    scenes.push_back(medium(o));
    scenes.push_back(large(o));
    scenes.push_back(coplanar(o));
    scenes.push_back(copy(o));
    for (double d : {1e-9, 1e-12, 1e-15}) scenes.push_back(near_touching(o, d));
    int frames = o.frames > 0 ? o.frames : (o.full ? 200 : 4);
    for (auto& s : scenes) s.frames = frames;
    return scenes;
}

std::vector<SelfScene> make_self_scenes(const SceneOptions& o) {
    std::vector<SelfScene> scenes;
    scenes.push_back(roll(o));
    scenes.push_back(crumple(o));
    scenes.push_back(fold(o));
    scenes.push_back(twist(o));
    int frames = o.frames > 0 ? o.frames : (o.full ? 40 : 5);
    for (auto& s : scenes) s.frames = frames;
    return scenes;
}

}  // namespace xc
