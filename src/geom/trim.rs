//! Inside/outside a face's trimming loops, in UV space.
