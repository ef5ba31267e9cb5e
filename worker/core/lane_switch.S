// The stack switch of lanes (lanes.h): saves the callee-saved registers of the System V x86-64
// ABI on the current stack, stores the stack pointer in *from and resumes the stack at `to` the
// same way. Floating-point control words and the signal mask are not switched: the lanes of one
// tracing thread share them. Measured against Boost.Context and ucontext in bench/batching.
//   void tessera_lane_switch(void** from /* rdi */, void* to /* rsi */);
// A lane's first switch lands in tessera_lane_start, which calls r13(r12) (LaneStack::Start lays
// them out) on a 16-byte aligned stack.
    .text
    .globl tessera_lane_switch
    .hidden tessera_lane_switch
    .type tessera_lane_switch, @function
tessera_lane_switch:
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
    // Not `ret`: the return stack buffer would predict a return to this stack's own caller, wrong
    // after every switch (twice the time in bench/batching); an indirect jump is predicted from
    // its own history.
    popq %rcx
    jmpq *%rcx
    .size tessera_lane_switch, .-tessera_lane_switch

    .globl tessera_lane_start
    .hidden tessera_lane_start
    .type tessera_lane_start, @function
tessera_lane_start:
    .cfi_startproc
    // The outermost frame of a lane: unwinders and backtraces stop here.
    .cfi_undefined rip
    movq %r12, %rdi
    call *%r13
    ud2
    .cfi_endproc
    .size tessera_lane_start, .-tessera_lane_start
    .section .note.GNU-stack,"",@progbits
