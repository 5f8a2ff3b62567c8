# cmake -DHEADER=<file.hpp> -P ArphysHardenLcmDecode.cmake
#
# lcm-gen 1.3.1 trusts the array counts and string lengths it reads from the wire:
# a 30-byte message announcing 2^31 elements makes the decoder allocate (and zero)
# gigabytes before it notices the buffer is short, and a length of 0 or less makes
# std::string::assign throw. It also initialises msg_hash (a -Wmaybe-uninitialized false positive). Every encoded element takes at least one byte, so a
# count larger than the bytes left is malformed: reject it before allocating.
file(READ ${HEADER} text)
string(REGEX REPLACE
  "([ ]*)this->([A-Za-z0-9_]+)\\.resize\\(this->([A-Za-z0-9_]+)\\);"
  "\\1if(this->\\3 < 0 || this->\\3 > maxlen - pos) return -1;\n\\1this->\\2.resize(this->\\3);"
  text "${text}")
string(REGEX REPLACE
  "if\\((__[A-Za-z0-9_]+) > maxlen - pos\\) return -1;"
  "if(\\1 < 1 || \\1 > maxlen - pos) return -1;"
  text "${text}")
# GCC 12 cannot see that the hash is always written before it is compared.
string(REPLACE "int64_t msg_hash;" "int64_t msg_hash = 0;" text "${text}")
file(WRITE ${HEADER} "${text}")
