// generators: being written
