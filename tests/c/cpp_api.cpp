// C++17 link test of the katachi C ABI: the header compiles as C++ (extern "C", a uint32_t
// enum), handles live in std::unique_ptr, buffers in std::vector, and each thread reads its
// own last error message while other threads fail at the same time. Run by
// `cargo xtask ctest` under valgrind.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "katachi.h"

#include "check.h"
#include "shapes.h"

static_assert(sizeof(KatachiStatus) == 4, "KatachiStatus is a uint32_t");
static_assert(std::is_same<std::underlying_type<KatachiStatus>::type, uint32_t>::value,
              "KatachiStatus's underlying type is uint32_t in C++");
static_assert(KATACHI_ABI_VERSION >= 1, "the ABI version macro is an integer constant");
static_assert(std::is_standard_layout<KatachiMeshInfo>::value, "KatachiMeshInfo is a C struct");

namespace {

struct MeshFree {
    void operator()(KatachiMesh *m) const noexcept { katachi_mesh_free(m); }
};
using Mesh = std::unique_ptr<KatachiMesh, MeshFree>;

// Takes ownership of the handle a create/clone/read call writes into.
class MeshOut {
  public:
    explicit MeshOut(Mesh &target) : target_(target) {}
    ~MeshOut() { target_.reset(raw_); }
    MeshOut(const MeshOut &) = delete;
    MeshOut &operator=(const MeshOut &) = delete;
    operator KatachiMesh **() { return &raw_; }

  private:
    Mesh &target_;
    KatachiMesh *raw_ = nullptr;
};

std::string last_message() { return katachi_last_error_message(); }

Mesh make_plate()
{
    Mesh m;
    CHECK_OK("c++: create the plate with holes",
             katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12, PLATE_FACE_LOOP_COUNTS,
                                 10, PLATE_CORNERS, 48, MeshOut(m)));
    return m;
}

void test_header_in_cpp()
{
    CHECK("c++: abi version", katachi_abi_version() == KATACHI_ABI_VERSION);
    const std::string expected = std::to_string(KATACHI_VERSION_MAJOR) + "." +
                                 std::to_string(KATACHI_VERSION_MINOR) + "." +
                                 std::to_string(KATACHI_VERSION_PATCH);
    CHECK("c++: version string", expected == katachi_version_string());
    KatachiStatus s = KATACHI_STATUS_BAD_TOPOLOGY;
    CHECK("c++: statuses are enum values", static_cast<uint32_t>(s) == 5u);
    CHECK("c++: status name", std::string(katachi_status_name(s)) == "KATACHI_STATUS_BAD_TOPOLOGY");
    CHECK("c++: counts default", katachi_mesh_counts_default().struct_size == sizeof(KatachiMeshCounts));
    CHECK("c++: info default", katachi_mesh_info_default().struct_size == sizeof(KatachiMeshInfo));
}

void test_plate_with_vectors()
{
    Mesh plate = make_plate();
    if (!plate) return;
    KatachiMeshCounts c = katachi_mesh_counts_default();
    CHECK_OK("c++: counts", katachi_mesh_counts(plate.get(), &c));

    std::vector<double> pos(3 * static_cast<size_t>(c.vertex_count));
    std::vector<uint32_t> ls(c.loop_count), flc(c.face_count), cs(c.corner_count);
    CHECK_OK("c++: copy positions", katachi_mesh_copy_positions(plate.get(), pos.data(), pos.size()));
    CHECK_OK("c++: copy faces", katachi_mesh_copy_faces(plate.get(), ls.data(), ls.size(),
                                                        flc.data(), flc.size(), cs.data(), cs.size()));
    CHECK("c++: positions bit-exact",
          std::memcmp(pos.data(), PLATE_POSITIONS, sizeof PLATE_POSITIONS) == 0);
    CHECK("c++: two faces with two loops each, outer loop first",
          flc == std::vector<uint32_t>(PLATE_FACE_LOOP_COUNTS, PLATE_FACE_LOOP_COUNTS + 10) &&
              cs == std::vector<uint32_t>(PLATE_CORNERS, PLATE_CORNERS + 48) &&
              ls == std::vector<uint32_t>(PLATE_LOOP_SIZES, PLATE_LOOP_SIZES + 12));

    // Rebuild from what was copied out: the same mesh.
    Mesh again;
    CHECK_OK("c++: create from the copied-out arrays",
             katachi_mesh_create(pos.data(), c.vertex_count, ls.data(), c.loop_count, flc.data(),
                                 c.face_count, cs.data(), c.corner_count, MeshOut(again)));
    KatachiMeshInfo a = katachi_mesh_info_default(), b = katachi_mesh_info_default();
    CHECK_OK("c++: inspect the plate", katachi_mesh_inspect(plate.get(), &a));
    CHECK_OK("c++: inspect the rebuilt plate", katachi_mesh_inspect(again.get(), &b));
    CHECK("c++: plate genus 1 with 2 faces with holes",
          a.genus == 1 && a.faces_with_holes_count == 2 && a.edge_count == 24);
    CHECK("c++: rebuilt plate inspects the same",
          a.edge_count == b.edge_count && a.genus == b.genus &&
              a.euler_characteristic == b.euler_characteristic &&
              a.faces_with_holes_count == b.faces_with_holes_count &&
              a.bounding_box_max[2] == b.bounding_box_max[2]);

    // Crease the hole's rim on the top face and clone.
    const std::vector<uint32_t> rim = {12, 13, 13, 14, 14, 15, 15, 12};
    const std::vector<double> sharp(4, 10.0);
    CHECK_OK("c++: crease the hole's rim",
             katachi_mesh_set_edge_sharpnesses(plate.get(), rim.data(), sharp.data(), sharp.size()));
    Mesh copy;
    CHECK_OK("c++: clone", katachi_mesh_clone(plate.get(), MeshOut(copy)));
    CHECK_OK("c++: counts of the clone", katachi_mesh_counts(copy.get(), &c));
    std::vector<uint32_t> e(2 * static_cast<size_t>(c.sharp_edge_count));
    std::vector<double> v(c.sharp_edge_count);
    CHECK_OK("c++: copy the clone's sharp edges",
             katachi_mesh_copy_sharp_edges(copy.get(), e.data(), v.data(), v.size()));
    CHECK("c++: the clone has the 4 creases",
          e == std::vector<uint32_t>({12, 13, 12, 15, 13, 14, 14, 15}) &&
              v == std::vector<double>(4, 10.0));
    double s = 0.0;
    CHECK_OK("c++: read one crease", katachi_mesh_edge_sharpness(copy.get(), 15, 12, &s));
    CHECK("c++: it is infinitely sharp", s == 10.0);
    CHECK_OK("c++: sharpen a corner of the clone", katachi_mesh_set_vertex_sharpness(copy.get(), 12, 2.0));
    std::vector<double> vs(c.vertex_count);
    CHECK_OK("c++: copy vertex sharpness", katachi_mesh_copy_vertex_sharpness(copy.get(), vs.data(), vs.size()));
    CHECK_OK("c++: read the corner", katachi_mesh_vertex_sharpness(copy.get(), 12, &s));
    CHECK("c++: corner sharpness", s == 2.0 && vs[12] == 2.0 && vs[0] == 0.0);
    std::fill(vs.begin(), vs.end(), 0.5);
    CHECK_OK("c++: set all vertex sharpness",
             katachi_mesh_set_all_vertex_sharpness(copy.get(), vs.data(), vs.size()));
    CHECK_OK("c++: the original keeps its corners", katachi_mesh_vertex_sharpness(plate.get(), 12, &s));
    CHECK("c++: the original's corner is smooth", s == 0.0);
    CHECK_OK("c++: smooth one crease", katachi_mesh_set_edge_sharpness(copy.get(), 12, 13, 0.0));
}

// Each thread makes a different failing call at the same time and must read its own message.
void test_messages_are_per_thread()
{
    Mesh plate = make_plate();
    if (!plate) return;
    const KatachiMesh *shared = plate.get();
    constexpr int kThreads = 4;
    constexpr int kRounds = 200;
    std::atomic<int> ready{0};
    std::vector<int> wrong(kThreads, 0);
    std::vector<std::string> example(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; t++) {
        threads.emplace_back([&, t] {
            ready.fetch_add(1);
            while (ready.load() < kThreads) std::this_thread::yield();
            for (int r = 0; r < kRounds; r++) {
                // Thread t asks for vertex 100 + t: out of range, so its message names 100 + t.
                const uint32_t vertex = 100u + static_cast<uint32_t>(t);
                double s = 0.0;
                KatachiStatus st = katachi_mesh_vertex_sharpness(shared, vertex, &s);
                const std::string m = last_message();
                const std::string want = "vertex = " + std::to_string(vertex) + " is out of range";
                if (st != KATACHI_STATUS_INVALID_ARGUMENT || m.find(want) == std::string::npos) {
                    wrong[t]++;
                    example[t] = m;
                }
                // A read-only call on the shared mesh succeeds and clears only this thread's message.
                KatachiMeshCounts c = katachi_mesh_counts_default();
                if (katachi_mesh_counts(shared, &c) != KATACHI_STATUS_OK || !last_message().empty() ||
                    c.loop_count != 12) {
                    wrong[t]++;
                }
            }
        });
    }
    CHECK_ERR("c++: the main thread fails too", katachi_mesh_counts(nullptr, nullptr),
              KATACHI_STATUS_NULL_POINTER, "mesh is NULL");
    for (auto &th : threads) th.join();
    for (int t = 0; t < kThreads; t++) {
        const std::string name = "c++: thread " + std::to_string(t) + " read only its own messages";
        CHECK(name.c_str(), wrong[t] == 0);
        if (wrong[t] != 0) printf("     e.g. \"%s\"\n", example[t].c_str());
    }
    CHECK("c++: the main thread's message is its own",
          last_message() == "katachi_mesh_counts: mesh is NULL");
}

void test_errors_in_cpp()
{
    Mesh m;
    std::vector<double> pos(PLATE_POSITIONS, PLATE_POSITIONS + 48);
    pos[7] = std::numeric_limits<double>::quiet_NaN();
    CHECK_ERR("c++: NaN coordinate",
              katachi_mesh_create(pos.data(), 16, PLATE_LOOP_SIZES, 12, PLATE_FACE_LOOP_COUNTS, 10,
                                  PLATE_CORNERS, 48, MeshOut(m)),
              KATACHI_STATUS_BAD_INPUT, "vertex 2: coordinate y is NaN");
    CHECK("c++: no handle after failure", !m);
    // A hole with only two vertices (the next loop takes the other two corners).
    std::vector<uint32_t> ls(PLATE_LOOP_SIZES, PLATE_LOOP_SIZES + 12);
    ls[1] = 2;
    ls[2] = 6;
    CHECK_ERR("c++: a hole with two vertices",
              katachi_mesh_create(PLATE_POSITIONS, 16, ls.data(), 12, PLATE_FACE_LOOP_COUNTS, 10,
                                  PLATE_CORNERS, 48, MeshOut(m)),
              KATACHI_STATUS_BAD_INPUT, "face 0, loop 1");
    CHECK_ERR("c++: read a missing file",
              katachi_mesh_read("/nonexistent/katachi/plate.obj", MeshOut(m)),
              KATACHI_STATUS_IO_ERROR, "/nonexistent/katachi/plate.obj");
    CHECK_ERR("c++: write a missing mesh", katachi_mesh_write(nullptr, "/tmp/x.obj"),
              KATACHI_STATUS_NULL_POINTER, "mesh is NULL");
}

} // namespace

int main()
{
    printf("katachi %s, from C++17\n", katachi_version_string());
    test_header_in_cpp();
    test_plate_with_vectors();
    test_messages_are_per_thread();
    test_errors_in_cpp();
    return check_finish();
}
