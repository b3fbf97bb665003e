// How the public API's entry points report failure: no exception crosses
// the API (include/invmap/invmap.h); inside, a bad argument throws
// std::invalid_argument (INVMAP_VERIFY) and the entry point turns it, or
// running out of memory, or a bug, into an Error with a message.
#pragma once

#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "invmap/invmap.h"

namespace invmap::engine {

/// Runs `body` (which returns an Error) and maps what it throws:
/// std::invalid_argument to InvalidArgument with its text, std::bad_alloc to
/// OutOfMemory, any other exception to Internal. `message`, when not null,
/// receives the text.
template <typename Body>
Error Guarded(std::string* message, Body&& body) {
  const auto say = [message](const std::string& text) {
    if (message) *message = text;
  };
  try {
    return body();
  } catch (const std::invalid_argument& e) {
    say(e.what());
    return Error::InvalidArgument;
  } catch (const std::bad_alloc&) {
    say("out of memory");
    return Error::OutOfMemory;
  } catch (const std::exception& e) {
    say(std::string("internal error: ") + e.what());
    return Error::Internal;
  }
}

}  // namespace invmap::engine
