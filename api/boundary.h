#pragma once
// The C boundary: every C function runs its body through guarded(), so no exception crosses it
// and each failure becomes a status and a message (include/deixis/deixis.h, "Errors").
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "deixis/deixis.h"

namespace deixis::api {

// A caller's mistake (null handle, wrong ABI, a value out of range): its own status, whatever
// the call's usual one.
struct CallError : Error {
  CallError(deixis_status s, const std::string& message) : Error(message), status(s) {}
  deixis_status status;
};

inline void require(bool ok, const char* message) {
  if (!ok) {
    throw CallError(DEIXIS_ERROR_INVALID_ARGUMENT, message);
  }
}

void check_abi(std::uint32_t abi_version);

// Runs `body`; a deixis::Error becomes `error_status` (DEIXIS_ERROR_FILE for loaders), and its
// message goes to `report(status, message)`.
template <class Body, class Report>
deixis_status guarded(deixis_status error_status, Body&& body, Report&& report) noexcept {
  try {
    body();
    return DEIXIS_OK;
  } catch (const CallError& e) {
    report(e.status, e.what());
    return e.status;
  } catch (const std::bad_alloc&) {
    report(DEIXIS_ERROR_OUT_OF_MEMORY, "out of memory");
    return DEIXIS_ERROR_OUT_OF_MEMORY;
  } catch (const std::invalid_argument& e) {
    report(DEIXIS_ERROR_INVALID_ARGUMENT, e.what());
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  } catch (const Error& e) {
    report(error_status, e.what());
    return error_status;
  } catch (const std::exception& e) {
    report(DEIXIS_ERROR_INTERNAL, e.what());
    return DEIXIS_ERROR_INTERNAL;
  } catch (...) {
    report(DEIXIS_ERROR_INTERNAL, "unknown exception");
    return DEIXIS_ERROR_INTERNAL;
  }
}

// Writes into a caller's deixis_error (which may be null), truncating at a UTF-8 boundary.
void write_error(deixis_error* error, deixis_status status, const char* message) noexcept;

// A create function's body: the error goes to the caller's deixis_error; OK clears it.
template <class Body>
deixis_status create_guarded(deixis_error* error, deixis_status error_status,
                             Body&& body) noexcept {
  const deixis_status status = guarded(
      error_status, body, [&](deixis_status s, const char* m) { write_error(error, s, m); });
  if (status == DEIXIS_OK) {
    write_error(error, DEIXIS_OK, "");
  }
  return status;
}

// A call on a handle: the error is kept as the handle's last error (a std::string the handle
// owns; assigning may allocate, but only when something failed).
template <class Body>
deixis_status handle_guarded(std::string* last_error, Body&& body) noexcept {
  return guarded(DEIXIS_ERROR_INVALID_ARGUMENT, body, [&](deixis_status, const char* m) {
    if (last_error != nullptr) {
      try {
        *last_error = m;
      } catch (...) {
        last_error->clear();
      }
    }
  });
}

}  // namespace deixis::api
