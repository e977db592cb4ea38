// What decides that a record answers a cell, and the file name of a cell's record (issue 11 A1).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "harness/record_type.h"

namespace sb {

// What a user asks for when naming a cell: the scene spec, light index, mode, scheme with its
// resolved parameters, resolution, tile size and part size (builds in parts only). Records of one
// request that differ in their identity are an older and a newer answer to it (an edited scene):
// the newer supersedes.
nlohmann::json recordRequest(const Record& record);

// The request with everything that decides the result: the scene's name and hash (its content),
// the fitted light and the record format. A record is reused for a cell only when the identities
// are equal.
nlohmann::json recordIdentity(const Record& record);

// The readable part of a record's file name:
//   <scene>_<light index>_<mode>_<scheme>[_<param>-<value>...]_<resolution>[_parts-<part size>]
// lower case, characters [a-z0-9_.-] only, at most 190 characters. Records written before the
// request hash was added are named by this alone.
std::string readableCellKey(const Record& record);

// readableCellKey + "_" + 8 hex digits of a hash of recordRequest: requests that read alike (two
// "model" scenes from different folders) get different files, while a rebuilt cell of an edited
// scene replaces its record at the same name. Needs only the identifying fields, so a sweep can
// name a cell before building it. The record file of a cell is cellKey(record) + ".json".
std::string cellKey(const Record& record);

// `text` reduced to [a-z0-9.-] for use inside file names: lower case, other characters become
// '-', runs of '-' collapse. Text with characters beyond ordinary punctuation gets a short hash
// of the original appended, so that different names stay different files. Never empty.
std::string fileNamePart(std::string_view text);

}  // namespace sb
