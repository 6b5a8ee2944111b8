//! tabula-tasks's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod clearing;
mod mock_driver;
mod placing;
mod shelves;
mod tidying;
