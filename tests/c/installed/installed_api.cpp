// C++17 test of an *installed* katachi. `cargo xtask install-test` installs the library into a
// fresh prefix and builds this file with nothing but
//
//     g++ -std=c++17 installed_api.cpp $(pkg-config --cflags --libs katachi)
//         -DKATACHI_EXPECTED_VERSION="\"$(pkg-config --modversion katachi)\""   (one line)
//
// so <katachi.h> is the installed header and -lkatachi the installed libkatachi.so; then it
// runs the program under valgrind with argv[1] = an all-quad model (fandisk_quads.off).
// Checks: the library, header and .pc file agree on the version; a cube subdivides to the
// known counts and corner position; the model subdivides to 16 quads per quad; bad input fails
// with a message naming the element (face and loop), and leaves the input as it was.
#include <katachi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "../check.h"
#include "../shapes.h"

#ifndef KATACHI_EXPECTED_VERSION
#error "build with -DKATACHI_EXPECTED_VERSION=\"\\\"<pkg-config --modversion katachi>\\\"\""
#endif

namespace {

struct Free {
    void operator()(KatachiMesh *m) const noexcept { katachi_mesh_free(m); }
    void operator()(KatachiSubdivision *s) const noexcept { katachi_subdivision_free(s); }
};
using Mesh = std::unique_ptr<KatachiMesh, Free>;
using Subdivision = std::unique_ptr<KatachiSubdivision, Free>;

// Runs a call that writes a handle into `T **`, taking ownership of whatever it wrote.
template <typename T, typename Call> std::unique_ptr<T, Free> out_handle(Call call, KatachiStatus &status)
{
    T *raw = nullptr;
    status = call(&raw);
    return std::unique_ptr<T, Free>(raw);
}

KatachiMeshCounts counts_of(const KatachiMesh *m)
{
    KatachiMeshCounts c = katachi_mesh_counts_default();
    CHECK_OK("counts", katachi_mesh_counts(m, &c));
    return c;
}

void test_versions()
{
    const std::string header_version = std::to_string(KATACHI_VERSION_MAJOR) + "." +
                                       std::to_string(KATACHI_VERSION_MINOR) + "." +
                                       std::to_string(KATACHI_VERSION_PATCH);
    CHECK("library version is the .pc file's Version",
          std::string(katachi_version_string()) == KATACHI_EXPECTED_VERSION);
    CHECK("installed header's version macros are the .pc file's Version",
          header_version == KATACHI_EXPECTED_VERSION);
    CHECK("library ABI is the installed header's", katachi_abi_version() == KATACHI_ABI_VERSION);
}

void test_cube()
{
    KatachiStatus st;
    Mesh cube = out_handle<KatachiMesh>(
        [](KatachiMesh **o) {
            return katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS,
                                       6, CUBE_CORNERS, 24, o);
        },
        st);
    if (!CHECK_OK("create the cube", st)) return;

    const KatachiSubdivideOptions options = katachi_subdivide_options_default();
    Subdivision s = out_handle<KatachiSubdivision>(
        [&](KatachiSubdivision **o) { return katachi_subdivide(cube.get(), &options, o); }, st);
    if (!CHECK_OK("subdivide the cube once (the default)", st)) return;
    Mesh out = out_handle<KatachiMesh>(
        [&](KatachiMesh **o) { return katachi_subdivision_mesh(s.get(), o); }, st);
    if (!CHECK_OK("the refined cube", st)) return;

    const KatachiMeshCounts c = counts_of(out.get());
    CHECK("cube: 26 vertices, 24 quads, 96 corners",
          c.vertex_count == 26 && c.face_count == 24 && c.loop_count == 24 && c.corner_count == 96);
    std::vector<double> pos(3 * static_cast<size_t>(c.vertex_count));
    CHECK_OK("copy the refined positions",
             katachi_mesh_copy_positions(out.get(), pos.data(), pos.size()));
    // Corner 7 = (1/2, 1/2, 1/2): valence 3, so its vertex point is (Q + 2R) / 3 = 5/9 of it
    // (seed 001 eq. (2)).
    bool corner = pos.size() == 78;
    for (int axis = 0; corner && axis < 3; axis++) {
        corner = std::fabs(pos[7 * 3 + axis] - 5.0 / 18.0) < 1e-15;
    }
    CHECK("cube: corner 7 moves to 5/18 (1, 1, 1)", corner);
}

void test_model(const char *path)
{
    KatachiStatus st;
    Mesh model = out_handle<KatachiMesh>([&](KatachiMesh **o) { return katachi_mesh_read(path, o); }, st);
    if (!CHECK_OK("read the model", st)) return;
    const KatachiMeshCounts in = counts_of(model.get());
    CHECK("model: fandisk_quads has 766 vertices and 764 quads",
          in.vertex_count == 766 && in.face_count == 764 && in.corner_count == 4 * 764);

    KatachiSubdivideOptions options = katachi_subdivide_options_default();
    options.levels = 2;
    Subdivision s = out_handle<KatachiSubdivision>(
        [&](KatachiSubdivision **o) { return katachi_subdivide(model.get(), &options, o); }, st);
    if (!CHECK_OK("subdivide the model twice", st)) return;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    CHECK_OK("subdivision info", katachi_subdivision_info(s.get(), &info));
    CHECK("model: 16 faces per quad after 2 levels, no fallback",
          info.levels == 2 && info.face_count == 16 * 764 && info.fallback_face_count == 0);

    Mesh out = out_handle<KatachiMesh>(
        [&](KatachiMesh **o) { return katachi_subdivision_mesh(s.get(), o); }, st);
    if (!CHECK_OK("the refined model", st)) return;
    const KatachiMeshCounts c = counts_of(out.get());
    std::vector<uint32_t> loop_sizes(c.loop_count), face_loops(c.face_count), corners(c.corner_count);
    CHECK_OK("copy the refined faces",
             katachi_mesh_copy_faces(out.get(), loop_sizes.data(), loop_sizes.size(),
                                     face_loops.data(), face_loops.size(), corners.data(),
                                     corners.size()));
    bool all_quads = c.face_count == 16 * 764 && c.loop_count == c.face_count;
    for (size_t i = 0; all_quads && i < loop_sizes.size(); i++) {
        all_quads = loop_sizes[i] == 4 && face_loops[i] == 1;
    }
    CHECK("model: every refined face is a quad with one loop", all_quads);

    std::vector<uint32_t> origin(c.face_count);
    CHECK_OK("copy face origins",
             katachi_subdivision_copy_face_origin(s.get(), origin.data(), origin.size()));
    std::vector<uint32_t> children(in.face_count, 0);
    bool in_range = true;
    for (uint32_t f : origin) {
        if (f < children.size()) {
            children[f]++;
        } else {
            in_range = false;
        }
    }
    bool sixteen = in_range;
    for (uint32_t n : children) {
        sixteen = sixteen && n == 16;
    }
    CHECK("model: each input quad is the origin of exactly 16 refined faces", sixteen);
}

void test_errors()
{
    KatachiStatus st;
    // A face naming vertex 9 of 8: refused, and the message names the face, loop and vertex.
    std::vector<uint32_t> bad(CUBE_CORNERS, CUBE_CORNERS + 24);
    bad[5] = 9;
    Mesh none = out_handle<KatachiMesh>(
        [&](KatachiMesh **o) {
            return katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS,
                                       6, bad.data(), 24, o);
        },
        st);
    CHECK_ERR("create: a vertex index out of range", st, KATACHI_STATUS_BAD_INPUT,
              "face 1, loop 0: vertex index 9 is out of range (the mesh has 8 vertices)");
    CHECK("create: no mesh on failure", none == nullptr);

    // The plate of shapes.h with the top face's hole wound like its outer loop: each loop is
    // valid, but the face is not, and subdivision says which face and loop.
    std::vector<uint32_t> corners(PLATE_CORNERS, PLATE_CORNERS + 48);
    std::reverse(corners.begin() + 4, corners.begin() + 8);
    Mesh plate = out_handle<KatachiMesh>(
        [&](KatachiMesh **o) {
            return katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12,
                                       PLATE_FACE_LOOP_COUNTS, 10, corners.data(), 48, o);
        },
        st);
    if (!CHECK_OK("create a plate whose hole runs the wrong way", st)) return;
    const KatachiSubdivideOptions options = katachi_subdivide_options_default();
    Subdivision s = out_handle<KatachiSubdivision>(
        [&](KatachiSubdivision **o) { return katachi_subdivide(plate.get(), &options, o); }, st);
    CHECK_ERR("subdivide: a hole wound like its outer loop", st, KATACHI_STATUS_BAD_INPUT,
              "face 0: hole (loop 1) runs the same way as the outer loop");
    CHECK("subdivide: no result on failure", s == nullptr);
    const KatachiMeshCounts c = counts_of(plate.get());
    CHECK("subdivide: the input is untouched",
          c.vertex_count == 16 && c.face_count == 10 && c.loop_count == 12);
    std::vector<uint32_t> ls(c.loop_count), flc(c.face_count), cs(c.corner_count);
    CHECK_OK("copy the plate's faces after the failure",
             katachi_mesh_copy_faces(plate.get(), ls.data(), ls.size(), flc.data(), flc.size(),
                                     cs.data(), cs.size()));
    CHECK("subdivide: the input's corners are unchanged", cs == corners);

    Mesh missing = out_handle<KatachiMesh>(
        [](KatachiMesh **o) { return katachi_mesh_read("/nonexistent/katachi/model.off", o); }, st);
    CHECK_ERR("read: a missing file names its path", st, KATACHI_STATUS_IO_ERROR,
              "/nonexistent/katachi/model.off");
    CHECK("read: no mesh on failure", missing == nullptr);
}

} // namespace

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s ALL_QUAD_MODEL (fandisk_quads.off)\n", argv[0]);
        return 2;
    }
    test_versions();
    test_cube();
    test_model(argv[1]);
    test_errors();
    return check_finish();
}
