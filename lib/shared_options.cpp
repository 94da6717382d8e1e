#include "lib/shared_options.h"

#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

std::string_view shared_option_help(Option option) {
  switch (option) {
    case Option::tol:
      return "The reference's absolute tolerance on I, per ray (each pixel, each channel)";
    case Option::width:
      return "The camera's width in pixels (the rays of a fan), in place of the scene's";
    case Option::height:
      return "The camera's height in pixels (1 for a fan), in place of the scene's";
    default:
      throw std::invalid_argument(
          fmt::format("shared_option_help: '{}' is not a shared option", option_name(option, Spelling::key)));
  }
}

}  // namespace vrv
