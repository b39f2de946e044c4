//! JavaScript bindings (wasm32 only). FIRST VERSION: in progress (issue 2).
