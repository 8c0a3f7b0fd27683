// katachi-reference shim: result accessors and the base-mesh checks shared by both libraries.
#include "shim_internal.hpp"

#include <cmath>
#include <string>

namespace kr {

void check_mesh(const kr_mesh *mesh, uint32_t level) {
    if (mesh == nullptr) {
        throw BadArgument("mesh is null");
    }
    if (level > KR_MAX_LEVEL) {
        throw BadArgument("level " + std::to_string(level) + " is above the maximum " +
                          std::to_string(KR_MAX_LEVEL));
    }
    if (mesh->num_vertices > 0 && mesh->positions == nullptr) {
        throw BadArgument("positions are null");
    }
    if (mesh->num_faces > 0 && (mesh->face_sizes == nullptr || mesh->face_vertices == nullptr)) {
        throw BadArgument("face arrays are null");
    }
    // OpenSubdiv indexes with int.
    if (mesh->num_vertices > INT32_MAX / 4 || mesh->num_face_vertices > INT32_MAX / 4) {
        throw BadArgument("mesh too large for OpenSubdiv's int indices");
    }
    for (uint32_t v = 0; v < mesh->num_vertices; ++v) {
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(mesh->positions[3 * v + k])) {
                throw BadArgument("vertex " + std::to_string(v) + " has a non-finite coordinate");
            }
        }
    }
    uint64_t corners = 0;
    for (uint32_t f = 0; f < mesh->num_faces; ++f) {
        uint32_t n = mesh->face_sizes[f];
        if (n < 3) {
            throw BadArgument("face " + std::to_string(f) + " has " + std::to_string(n) +
                              " corners; at least 3 are needed");
        }
        if (corners + n > mesh->num_face_vertices) {
            throw BadArgument("face sizes add up to more than num_face_vertices (" +
                              std::to_string(mesh->num_face_vertices) + ")");
        }
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t v = mesh->face_vertices[corners + k];
            if (v >= mesh->num_vertices) {
                throw BadArgument("face " + std::to_string(f) + " refers to vertex " +
                                  std::to_string(v) + ", but the mesh has " +
                                  std::to_string(mesh->num_vertices) + " vertices");
            }
        }
        corners += n;
    }
    if (corners != mesh->num_face_vertices) {
        throw BadArgument("face sizes add up to " + std::to_string(corners) +
                          ", but num_face_vertices is " + std::to_string(mesh->num_face_vertices));
    }
}

}  // namespace kr

extern "C" {

const char *kr_result_message(const kr_result *result) {
    return result == nullptr ? "" : result->message.c_str();
}

const char *kr_result_warnings(const kr_result *result) {
    return result == nullptr ? "" : result->warnings.c_str();
}

const double *kr_result_f64(const kr_result *result, uint32_t array, uint32_t level, size_t *len) {
    if (len != nullptr) {
        *len = 0;
    }
    if (result == nullptr) {
        return nullptr;
    }
    auto it = result->f64.find(std::make_pair(array, level));
    if (it == result->f64.end()) {
        return nullptr;
    }
    if (len != nullptr) {
        *len = it->second.size();
    }
    return it->second.data();
}

const uint32_t *kr_result_u32(const kr_result *result, uint32_t array, uint32_t level, size_t *len) {
    if (len != nullptr) {
        *len = 0;
    }
    if (result == nullptr) {
        return nullptr;
    }
    auto it = result->u32.find(std::make_pair(array, level));
    if (it == result->u32.end()) {
        return nullptr;
    }
    if (len != nullptr) {
        *len = it->second.size();
    }
    return it->second.data();
}

void kr_result_free(kr_result *result) {
    delete result;
}

}  // extern "C"
