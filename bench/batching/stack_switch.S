// A stack switch of our own, to measure against Boost.Context (switches.cc): saves the
// callee-saved registers of the System V x86-64 ABI on the current stack, stores the stack
// pointer in *from, and resumes the stack at `to` the same way. No floating-point control words
// and no signal mask: the fibers of one tracing thread share both.
//   void tessera_bench_switch(void** from /* rdi */, void* to /* rsi */);
// A new stack starts in tessera_bench_start with the entry function in r13 and its argument in
// r12 (switches.cc lays them out).
    .text
    .globl tessera_bench_switch
    .type tessera_bench_switch, @function
tessera_bench_switch:
    pushq %rbp
    pushq %rbx
    pushq %r12
    pushq %r13
    pushq %r14
    pushq %r15
    movq %rsp, (%rdi)
    movq %rsi, %rsp
    popq %r15
    popq %r14
    popq %r13
    popq %r12
    popq %rbx
    popq %rbp
    // Not `ret`: the return stack buffer predicts a return to this stack's caller, which is
    // wrong after every switch; an indirect jump is predicted from its own history.
    popq %rcx
    jmpq *%rcx
    .size tessera_bench_switch, .-tessera_bench_switch

    .globl tessera_bench_start
    .type tessera_bench_start, @function
tessera_bench_start:
    movq %r12, %rdi
    call *%r13
    ud2
    .size tessera_bench_start, .-tessera_bench_start
    .section .note.GNU-stack,"",@progbits
