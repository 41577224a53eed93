// A film's exact state (film/film.h: its fixed-point sums and counts) in EXR channels beside the
// image, so that a render's output can be merged with other parts of the render (`dacrt merge`)
// or continued (`render --resume`) bit for bit. Each 128-bit sum is four 32-bit integer (UINT)
// channels, lowest word first: "exact.sums.0.w0" … "exact.sums.0.w3" is the red sum (the order
// of a pixel's sums is the film's); the counts are "exact.count", "exact.taken" and
// "exact.hits". The header's exactSums names the format. Albedo and normal sums, which the film
// keeps in 96 bits, are written sign-extended to four words, as earlier versions wrote them.
#pragma once

#include <string>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/io/exr.h"

namespace dacrt {

// The exactSums attribute of files this version writes; files with another are refused.
inline constexpr const char* exact_sums_format =
    "fixed128 v2: values in 2^-64, squares in 2^-46, clamped at 2^30, toward zero";

// The film's word channels, pointing into it (valid while the film lives and is not resized).
// The film keeps albedo and normal sums in 96 bits (Film::bounded): their fourth words point
// into `high` (resized by the caller to that many words a pixel), or nowhere without it. The
// counts (Film::count_value), which the film keeps packed, point into `counts`, made here with
// the film's counts (Film::counts_per_pixel() words a pixel), or nowhere without it.
std::vector<WordChannel> film_words(const Film& film, std::vector<uint32_t>* high = nullptr,
                                    std::vector<uint32_t>* counts = nullptr);

// The samplesPerPixel attribute: "every pixel N", or "from A to B (the samples.X channel)".
std::string samples_per_pixel_text(uint32_t least, uint32_t most);

// Writes a film as renders and merges do: its channels (Film::channels, with the samples channel
// when pixels have different counts), the metadata with the tallies (samplesDropped,
// samplesClamped) added, and with `exact` the word channels and exactSums.
void write_film_exr(const std::string& path, const Film& film, ExrMetadata metadata, bool exact);

// The header of `path`, which must hold exact sums of this version's format: Error naming the
// file otherwise, saying what it was to be read for (`purpose`: "to merge", "to resume from").
ExrHeader read_sums_header(const std::string& path, const std::string& purpose);

// Reads the exact state of `path` (its header: read_sums_header's) into `film` (empty, of the
// file's size and outputs): the word channels, and the tallies from samplesDropped and
// samplesClamped. Then checks it: every pixel took between `least` and `most` samples, has no
// more hits than samples and no sums its samples cannot add up to. Error naming the file (and
// the pixel) otherwise, also when an albedo or normal sum does not fit in 96 bits.
void read_film_state(const std::string& path, const ExrHeader& header, Film& film, uint32_t least,
                     uint32_t most);

}  // namespace dacrt
