pub mod constants;
pub mod core;
pub mod init;
pub mod math;
pub mod parsing;
pub mod yaml_utils;

// Re-export crate-internal parsing utilities
pub(crate) use parsing::{find_matching_paren, remove_quotes};

// Re-export crate-internal init utilities
pub(crate) use init::{format_value_python_style, init_interpreter};
// Re-export EvalError as pub so it can be exposed through error module
pub use init::EvalError;

// Re-export crate-internal core evaluation functions
pub(crate) use core::{build_pyisheval_context, eval_boolean};

// Re-export crate-public core functions (pub(crate))
pub(crate) use core::evaluate_expression_impl;
