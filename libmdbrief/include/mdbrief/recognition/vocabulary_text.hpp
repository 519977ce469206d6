#pragma once
// DBoW2 / DBoW3 text vocabularies of binary descriptors (ORB-SLAM's ORBvoc.txt), so existing
// vocabularies can be read, compared and exported. The format, as those libraries write it:
//   line 1:  k L scoring weighting            (DBoW2's numbering; weighting as Weighting)
//   then one line per node but the root, in node order (the root is node 0):
//            parent isLeaf byte_1 .. byte_B weight
// with the descriptor's B bytes as decimal numbers, every parent before its children, each
// node's children on consecutive lines, and the words the leaves in node order. Only plain
// (unmasked) vocabularies fit in it. The scoring type is not part of a Vocabulary (the Database
// scores L1): it is read and not kept, and written as 0 (L1).
#include <string>

#include "mdbrief/recognition/vocabulary.hpp"

namespace mdbrief {

// Reads a text vocabulary: a plain Vocabulary whose bits are 8 B (B a multiple of 4, 4..64).
// Every line and number is checked; throws FileFormatError naming the file, the line and the
// problem (e.g. a byte above 255, a width that changes, a parent after its child, children not
// on consecutive lines, a leaf flag that disagrees with the children, a tree deeper than L).
Vocabulary importDbow2Text(const std::string& path);

// The text of a plain vocabulary (inner nodes with weight 0, weights with 9 significant digits,
// so importing gives the same vocabulary back). Throws std::invalid_argument for a masked one:
// the format has no place for the masks.
std::string dbow2Text(const Vocabulary& vocabulary);
// Writes dbow2Text atomically. Throws std::runtime_error naming the path on failure.
void exportDbow2Text(const Vocabulary& vocabulary, const std::string& path);

}  // namespace mdbrief
