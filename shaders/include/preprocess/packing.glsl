// Unpacking of the byte-sized sensor formats from std430 uint words. Storage buffers of 8- or
// 16-bit types need optional device features (storageBuffer8/16BitAccess) that SBC GPUs may lack,
// so raw depth and colour are uploaded as the bytes of the host image and unpacked by shifts.
// Host-side mirrors: pipeline/preprocess/include/vifusion/preprocess/packing.hpp.
#ifndef VIFUSION_PREPROCESS_PACKING_GLSL
#define VIFUSION_PREPROCESS_PACKING_GLSL

// Raw depth: uint16 pixel i (row-major pixel index) lives in word i / 2, low 16 bits when i is even.
// The caller passes the word it read, raw_words[i >> 1].
uint depthOfWord(uint word, uint pixel_index) { return (word >> (16u * (pixel_index & 1u))) & 0xFFFFu; }

// Colour: byte k of the RGB888 image lives in word k / 4 at bits 8·(k % 4) (the bytes of the image
// exactly as a little-endian host holds them). The caller passes the word it read, rgb_words[k >> 2].
uint byteOfWord(uint word, uint byte_index) { return (word >> (8u * (byte_index & 3u))) & 0xFFu; }

#endif
