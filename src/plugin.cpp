// frix_plugin_api: the constant function table of include/frix/frix_plugin.h. The table is
// constant-initialised (no global mutable state), and each member is the exported function
// itself, so the compiler checks every member's type against the declaration it mirrors,
// and -Wmissing-field-initializers (-Wextra) catches a member appended to the header only.
#include <frix/frix.h>

#include <cstddef>

#include "error_state.hpp"

namespace {

// The members of table version 1 after its header, in order.
#define FRIX_TABLE_V1_FUNCTIONS \
    frix_version_string,\
    frix_error_string,\
    frix_status_string,\
    frix_last_error_message,\
    frix_matrix_from_csc,\
    frix_matrix_from_csr,\
    frix_matrix_from_triplets,\
    frix_matrix_from_dense,\
    frix_matrix_from_blocks,\
    frix_matrix_free,\
    frix_matrix_rows,\
    frix_matrix_cols,\
    frix_matrix_nnz,\
    frix_matrix_gemv,\
    frix_matrix_gemv_transposed,\
    frix_matrix_to_csc,\
    frix_matrix_block_count,\
    frix_matrix_is_block,\
    frix_matrix_diagonal_block,\
    frix_problem_local,\
    frix_problem_global,\
    frix_problem_free,\
    frix_problem_get_kind,\
    frix_problem_contacts,\
    frix_problem_contact_dofs,\
    frix_problem_dofs,\
    frix_problem_set_title,\
    frix_problem_title,\
    frix_problem_W,\
    frix_problem_M,\
    frix_problem_H,\
    frix_problem_q,\
    frix_problem_f,\
    frix_problem_w,\
    frix_problem_mu,\
    frix_options_create,\
    frix_options_copy,\
    frix_options_free,\
    frix_options_solver,\
    frix_options_set_int,\
    frix_options_set_double,\
    frix_options_get_int,\
    frix_options_get_double,\
    frix_options_bounds,\
    frix_option_name,\
    frix_option_by_name,\
    frix_options_set_callback,\
    frix_solver_count,\
    frix_solver_id_at,\
    frix_solver_name,\
    frix_solver_describe,\
    frix_solver_by_name,\
    frix_info_create,\
    frix_info_free,\
    frix_info_get_int,\
    frix_info_get_double,\
    frix_info_status,\
    frix_info_iterations,\
    frix_info_error,\
    frix_info_solve_time,\
    frix_solve,\
    frix_problem_measure,\
    frix_problem_error,\
    frix_read_problem,\
    frix_fclib_read,\
    frix_fclib_read_solution,\
    frix_fclib_write,\
    frix_dat_read,\
    frix_fclib_guess_count,\
    frix_fclib_read_guess,\
    frix_info_trace,\
    frix_problem_check_existence,\
    frix_existence_describe,\
    frix_options_set_log,\
    frix_info_stage_count,\
    frix_info_stage_get_int,\
    frix_info_stage_get_double,\
    frix_info_stage_note

// Version 1 ends where version 2's members begin; a host of version 1 never reads past it.
const frix_plugin_table kTableV1 = {
    offsetof(frix_plugin_table, persistent_create), 1, FRIX_VERSION_NUMBER, FRIX_TABLE_V1_FUNCTIONS,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
};

#define FRIX_TABLE_V2_FUNCTIONS \
    FRIX_TABLE_V1_FUNCTIONS,\
    frix_persistent_create,\
    frix_persistent_free,\
    frix_persistent_solve,\
    frix_persistent_update_local,\
    frix_persistent_update_global

// Version 2 ends where version 3's members begin.
const frix_plugin_table kTableV2 = {
    offsetof(frix_plugin_table, persistent_set_contacts_local), 2, FRIX_VERSION_NUMBER, FRIX_TABLE_V2_FUNCTIONS,
    nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
};

#define FRIX_TABLE_V3_FUNCTIONS \
    FRIX_TABLE_V2_FUNCTIONS,\
    frix_persistent_set_contacts_local,\
    frix_persistent_set_contacts_global

// Version 3 ends where version 4's members begin.
const frix_plugin_table kTableV3 = {
    offsetof(frix_plugin_table, option_choice_name), 3, FRIX_VERSION_NUMBER, FRIX_TABLE_V3_FUNCTIONS,
    nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
};

#define FRIX_TABLE_V4_FUNCTIONS \
    FRIX_TABLE_V3_FUNCTIONS,\
    frix_option_choice_name,\
    frix_option_choice_by_name,\
    frix_options_set_by_name

// Version 4 ends where version 5's members begin.
const frix_plugin_table kTableV4 = {
    offsetof(frix_plugin_table, problem_rolling_local), 4, FRIX_VERSION_NUMBER, FRIX_TABLE_V4_FUNCTIONS,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
};

#define FRIX_TABLE_V5_FUNCTIONS \
    FRIX_TABLE_V4_FUNCTIONS,\
    frix_problem_rolling_local,\
    frix_problem_rolling_global,\
    frix_problem_mu_r,\
    frix_problem_set_description,\
    frix_problem_description,\
    frix_problem_set_math_info,\
    frix_problem_math_info,\
    frix_fclib_write_compressed,\
    frix_persistent_set_contacts_rolling_local,\
    frix_persistent_set_contacts_rolling_global,\
    frix_persistent_update_mu_r

// Version 5 ends where version 6's members begin.
const frix_plugin_table kTableV5 = {
    offsetof(frix_plugin_table, problem_spinning_local), 5, FRIX_VERSION_NUMBER, FRIX_TABLE_V5_FUNCTIONS,
    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
};

const frix_plugin_table kTableV6 = {
    sizeof(frix_plugin_table),
    6,
    FRIX_VERSION_NUMBER,
    FRIX_TABLE_V5_FUNCTIONS,
    frix_problem_spinning_local,
    frix_problem_spinning_global,
    frix_problem_mu_s,
    frix_persistent_set_contacts_spinning_local,
    frix_persistent_set_contacts_spinning_global,
    frix_persistent_update_mu_s,
};

}  // namespace

extern "C" FRIX_API const frix_plugin_table *frix_plugin_api(int requested_abi_version) {
    const frix_plugin_table *table = nullptr;
    frix::guard("frix_plugin_api", [&]() -> frix_error {
        if (requested_abi_version == 1) table = &kTableV1;
        else if (requested_abi_version == 2) table = &kTableV2;
        else if (requested_abi_version == 3) table = &kTableV3;
        else if (requested_abi_version == 4) table = &kTableV4;
        else if (requested_abi_version == 5) table = &kTableV5;
        else if (requested_abi_version == 6) table = &kTableV6;
        else
            return frix::fail(FRIX_ERR_UNSUPPORTED,
                              "frix_plugin_api: table ABI version %d requested; libfrix %s serves "
                              "versions 1 to %d",
                              requested_abi_version, FRIX_VERSION_STRING, FRIX_PLUGIN_ABI_VERSION);
        return FRIX_OK;
    });
    return table;
}
