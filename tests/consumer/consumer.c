/* Converts the built-in sample in memory through the C API and writes the files into argv[1]. */
#include <ahd/ahd.h>
#include <ahd/sample.h>

#include <stdio.h>
#include <string.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: consumer_c OUTDIR PROFILE\n");
    return 2;
  }
  float* sh = NULL;
  unsigned char* coverage = NULL;
  if (ahd_sample_bake(256, 2, 0, &sh, &coverage) != 0) return 1;
  ahd_sh_input in = {256, 256, 9, sh, coverage, NULL};
  ahd_options opt;
  ahd_options_init(&opt);
  opt.profile = argv[2];
  ahd_result* result = NULL;
  char error[256];
  const int rc = ahd_convert(&in, "sample", &opt, &result, error, sizeof error);
  ahd_sample_free(sh);
  ahd_sample_free(coverage);
  if (rc != 0) {
    fprintf(stderr, "consumer_c: %s\n", error);
    return 1;
  }
  /* A bad option is refused with a message, not a crash. */
  opt.direction = 7;
  ahd_result* bad = NULL;
  if (ahd_convert(&in, "x", &opt, &bad, error, sizeof error) == 0 || bad != NULL || strstr(error, "direction") == NULL) {
    fprintf(stderr, "consumer_c: an invalid option was accepted\n");
    return 1;
  }
  for (size_t i = 0; i < ahd_result_file_count(result); ++i) {
    size_t size = 0;
    const unsigned char* data = ahd_result_file_data(result, i, &size);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", argv[1], ahd_result_file_name(result, i));
    FILE* f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size) return 1;
    fclose(f);
  }
  printf("%zu files, version %s\n", ahd_result_file_count(result), ahd_version());
  ahd_result_free(result);
  return 0;
}
