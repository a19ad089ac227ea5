/* Whole files for the test programs: read every byte of one, write given bytes or a string to
 * one. Any I/O failure fails the running Check test, naming the file. */
#ifndef FRIX_TEST_FILES_H
#define FRIX_TEST_FILES_H

/* The content of `path` (any bytes, NUL bytes included), NUL-terminated; its length in *size
 * unless size is NULL. The caller frees it. */
char *slurp(const char *path, long *size);

/* Writes the `size` bytes at `data` to `path`, replacing what was there. */
void spit(const char *path, const void *data, long size);

/* Writes the string `text` (without its NUL) to `path`, replacing what was there. */
void spit_text(const char *path, const char *text);

#endif
