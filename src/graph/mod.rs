//! The render graph: file formats ([`desc`]), shader reflection ([`reflect`]), the compiler
//! ([`compile`]) that turns a graph file into a [`compile::Plan`], and Graphviz output ([`dot`]).
//! Nothing here touches the GPU; [`crate::runtime`] executes plans.

pub mod builtins;
pub mod compile;
pub mod desc;
pub mod dot;
pub mod reflect;

pub use compile::{compile, Plan, Project};
