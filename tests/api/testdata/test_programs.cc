// A stand-in program module for host API tests: the host only checks that functions exist,
// so plain C functions suffice (no program-side headers needed).
extern "C" {
void ray_gen() {}
void exception() {}
void miss() {}
void closest_hit() {}
void any_hit() {}
void intersect(int) {}
void bounds(int, float*) {}
void visit() {}
}
