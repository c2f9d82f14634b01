//! FMI 2.0 layer (state machine and extern "C" functions).
