// Internal to the katachi-reference shim: the result handle, argument checks, the exception guard.
#ifndef KATACHI_REFERENCE_SHIM_INTERNAL_HPP
#define KATACHI_REFERENCE_SHIM_INTERNAL_HPP

#include "katachi_reference.h"

#include <cstdint>
#include <map>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

struct kr_result {
    std::string message;
    std::string warnings;
    std::map<std::pair<uint32_t, uint32_t>, std::vector<double>> f64;
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> u32;
};

namespace kr {

// Malformed arguments: becomes KR_STATUS_BAD_ARGUMENT.
struct BadArgument : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The library refused the input: becomes KR_STATUS_REJECTED.
struct Rejected : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Checks the base mesh: pointers, face sizes >= 3 adding up to num_face_vertices, indices in range,
// finite coordinates, level in range.
void check_mesh(const kr_mesh *mesh, uint32_t level);

// Runs `body(result)` on a fresh result, maps every exception to a status and a message.
template <class F>
uint32_t guarded(kr_result **out, F &&body) {
    if (out == nullptr) {
        return KR_STATUS_BAD_ARGUMENT;
    }
    *out = nullptr;
    kr_result *result = new (std::nothrow) kr_result();
    if (result == nullptr) {
        return KR_STATUS_EXCEPTION;
    }
    *out = result;
    try {
        body(*result);
        return KR_STATUS_OK;
    } catch (...) {
        // A failed call returns no partial arrays, only a status and a message.
        result->f64.clear();
        result->u32.clear();
        uint32_t status = KR_STATUS_EXCEPTION;
        try {
            try {
                throw;
            } catch (const BadArgument &e) {
                status = KR_STATUS_BAD_ARGUMENT;
                result->message = e.what();
            } catch (const Rejected &e) {
                status = KR_STATUS_REJECTED;
                result->message = e.what();
            } catch (const std::bad_alloc &) {
                result->message = "out of memory (std::bad_alloc)";
            } catch (const std::exception &e) {
                result->message = std::string("C++ exception: ") + e.what();
            } catch (...) {
                result->message = "unknown C++ exception";
            }
        } catch (...) {
            // Building the message itself failed (out of memory): keep the status.
        }
        return status;
    }
}

}  // namespace kr

#endif
