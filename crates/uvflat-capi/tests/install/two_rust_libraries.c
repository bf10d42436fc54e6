/* Links libuvflat.a and a second Rust static library into one program: both carry a Rust
 * runtime, so this links only when libuvflat.a exports nothing but its uvf_* functions. */
#include "uvflat.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

uint64_t other_rust_sum(uint32_t n);

int main(void) {
    const double positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t triangles[] = {0, 1, 2};
    UvfMeshInfo info;
    info.struct_size = sizeof info;
    if (uvf_mesh_info(positions, 3, triangles, 1, &info) != UVF_OK || info.boundary_loops != 1) return 1;
    if (other_rust_sum(10) != 45) return 2;
    printf("uvflat %s and another Rust library ok\n", uvf_version());
    return 0;
}
