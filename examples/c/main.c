/* Calling the generated filter functions from C.
 *
 * Generate and build (from the repository root):
 *
 *   observability codegen slam1.5d-beacon -o time=discrete --out build
 *   gcc -O2 -I build examples/c/main.c build/filter_functions.c -lm -o build/slam15d
 *   ./build/slam15d 1 0.5 3 0.2   0.95 0.5 3 0.2   20 0.1 0 0.5
 *
 * The twelve numbers are x = [c, cdot, x_L2, d_L2], x_prev (the same states one
 * step earlier) and p = [f, dt, x_L1, d_L1] (the order `codegen` prints). The
 * program prints the measurement h and its Jacobian H_Xk as dense matrices.
 *
 * Every C symbol carries the --name (default filter_functions): the function h is
 * filter_functions_h, so several generated models link into one program.
 * Every generated function F has the same calling convention (CasADi):
 *   F_work(&n_arg, &n_res, &n_iw, &n_w)   sizes of the work arrays
 *   mem = F_checkout(); F(arg, res, iw, w, mem); F_release(mem);
 *   arg[i] points to input i (dense, column-major), res[j] to the non-zeros of
 *   output j in the compressed-column pattern F_sparsity_out(j):
 *   {rows, columns, colind[columns + 1], row[nnz]}, or {rows, columns, 1} when
 *   the output is dense (colind[0] is always 0, so the 1 marks the short form).
 */
#include <stdio.h>
#include <stdlib.h>

#include "filter_functions.h"

typedef struct {
    const char *name;
    int (*eval)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);
    int (*work)(casadi_int *, casadi_int *, casadi_int *, casadi_int *);
    const casadi_int *(*sparsity_out)(casadi_int);
    int (*checkout)(void);
    void (*release)(int);
} generated_function;

/* Evaluate f at the given inputs and print output 0 densely; 0 on success. */
static int print_output(const generated_function *f, const casadi_real **inputs, casadi_int n_inputs) {
    casadi_int n_arg, n_res, n_iw, n_w;
    if (f->work(&n_arg, &n_res, &n_iw, &n_w)) return 1;
    const casadi_real **arg = calloc((size_t)n_arg, sizeof *arg);
    casadi_real **res = calloc((size_t)n_res, sizeof *res);
    casadi_int *iw = calloc((size_t)n_iw + 1, sizeof *iw);
    casadi_real *w = calloc((size_t)n_w + 1, sizeof *w);
    const casadi_int *sp = f->sparsity_out(0);
    casadi_int rows = sp[0], cols = sp[1];
    int dense = sp[2] == 1;
    const casadi_int *colind = sp + 2, *row = sp + 2 + cols + 1;
    casadi_int nnz = dense ? rows * cols : colind[cols];
    casadi_real *nz = calloc((size_t)nnz + 1, sizeof *nz);
    int status = 1;
    if (arg && res && iw && w && nz) {
        for (casadi_int i = 0; i < n_inputs; ++i) arg[i] = inputs[i];
        res[0] = nz;
        int mem = f->checkout();
        status = f->eval(arg, res, iw, w, mem);
        f->release(mem);
    }
    if (status == 0) {
        printf("%s %lld %lld", f->name, (long long)rows, (long long)cols);
        for (casadi_int r = 0; r < rows; ++r) {           /* row-major, zeros filled in */
            for (casadi_int c = 0; c < cols; ++c) {
                casadi_real value = 0;
                if (dense)
                    value = nz[c * rows + r];
                else
                    for (casadi_int k = colind[c]; k < colind[c + 1]; ++k)
                        if (row[k] == r) value = nz[k];
                printf(" %.17g", value);
            }
        }
        printf("\n");
    }
    free(arg); free(res); free(iw); free(w); free(nz);
    return status;
}

int main(int argc, char **argv) {
    casadi_real values[12] = {1, 0.5, 3, 0.2, 0.95, 0.5, 3, 0.2, 20, 0.1, 0, 0.5};
    if (argc != 1 && argc != 13) {
        fprintf(stderr, "usage: %s [c cdot x_L2 d_L2  c' cdot' x_L2' d_L2'  f dt x_L1 d_L1]\n", argv[0]);
        return 2;
    }
    for (int i = 1; i < argc; ++i) {
        char *end;
        values[i - 1] = strtod(argv[i], &end);
        if (*end != '\0') {
            fprintf(stderr, "%s: argument %d is not a number: %s\n", argv[0], i, argv[i]);
            return 2;
        }
    }
    const casadi_real *inputs[3] = {values, values + 4, values + 8}; /* x, x_prev, p */
    generated_function measurement = {"h", filter_functions_h, filter_functions_h_work, filter_functions_h_sparsity_out,
                                      filter_functions_h_checkout, filter_functions_h_release};
    generated_function jacobian = {"H_Xk", filter_functions_H_Xk, filter_functions_H_Xk_work,
                                   filter_functions_H_Xk_sparsity_out, filter_functions_H_Xk_checkout,
                                   filter_functions_H_Xk_release};
    if (print_output(&measurement, inputs, 3) || print_output(&jacobian, inputs, 3)) {
        fprintf(stderr, "%s: evaluation failed\n", argv[0]);
        return 1;
    }
    return 0;
}
